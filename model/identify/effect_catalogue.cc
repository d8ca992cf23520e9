#include "model/identify/effect_catalogue.h"

namespace orcs::identify {

const std::vector<EffectDescription>& EffectCatalogue() {
  static const std::vector<EffectDescription> catalogue{
      {"TransportDelay", "the command reaches the motor late", "velocity",
       {{"/Effects/TransportDelay/Delay", "s", 0.005, 0.15, true}}},
      {"DeadBand", "position errors within a margin are ignored", "command_error",
       {{"/Effects/DeadBand/Margin", "deg", 0.1, 6.0, true}}},
      // The servo model has its DC motor's back-EMF, its own compliance and its armature: these three are the
      // original model's stand-ins for them.
      {"BackEmf", "available torque falls with speed", "speed",
       {{"/Effects/BackEmf/NoLoadSpeed", "rad/s", 1.0, 50.0, true}}, true, false},
      {"Stribeck", "extra friction at low speed", "speed",
       {{"/Effects/Stribeck/BreakawayTorque", "N·m", 0.005, 0.5, true},
        {"/Effects/Stribeck/Velocity", "rad/s", 0.01, 1.0, true}}},
      {"LoadFriction", "gearbox friction grows with the transmitted torque", "load",
       {{"/Effects/LoadFriction/Coefficient", "1", 0.01, 1.0, true}}},
      {"Backlash", "the output turns freely within a gap", "load",
       {{"/Effects/Backlash/Width", "deg", 0.1, 8.0, true}}},
      {"Elasticity", "the gear train is a torsional spring", "acceleration",
       {{"/Effects/Elasticity/Stiffness", "N·m/rad", 0.5, 200.0, true}}, true, false},
      {"RotorInertia", "the reflected rotor inertia adds to the joint's", "acceleration",
       {{"/Effects/RotorInertia/Inertia", "kg·m²", 1e-4, 0.05, true}}, true, false},
      {"LuGre", "friction of elastic bristles: stiction built up over a presliding turn, lag", "speed",
       {{"/Effects/LuGre/StictionTorque", "N·m", 0.005, 0.5, true},
        {"/Effects/LuGre/CoulombTorque", "N·m", 0.002, 0.3, true},
        {"/Effects/LuGre/BristleStiffness", "N·m/rad", 1.0, 1000.0, true}}},
      // New with the servo model; the original model's diagnoses keep their nine candidates.
      {"GearEfficiency", "gearbox friction grows with the transmitted torque, faster under high load", "load",
       {{"/Effects/GearEfficiency/Coefficient", "1", 0.01, 1.0, true},
        {"/Effects/GearEfficiency/Curvature", "1", 0.0, 1.0, false}},
       false,
       true},
      {"BackDrive", "the gearbox brakes harder when the load drives it backwards", "load",
       {{"/Effects/BackDrive/Coefficient", "1", 0.01, 1.0, true}}, false, true},
      {"GravityLoadFriction", "gearbox friction grows with the load's pull against the motor (BAM's M3)", "load",
       {{"/Effects/GravityLoadFriction/Coefficient", "1", 0.01, 1.0, true}}, false, true},
      // Not a motor effect: one link of the robot is heavier or lighter than the model says (a payload, a battery,
      // a part the model lacks). The servos hide it from the joint angles as long as they have torque to spare;
      // the accelerometers feel it in the robot's sway.
      {"LinkMass", "a link's mass is off", "acceleration", {}, true, true, /*switched=*/false, /*per_link=*/true,
       /*needs_accelerometers=*/true},
  };
  return catalogue;
}

const EffectRelation* FindRelation(std::string_view a, std::string_view b) {
  static const std::vector<EffectRelation> relations{
      {"GearEfficiency", "LoadFriction", true,
       "GearEfficiency is LoadFriction with a curvature: at Curvature 0 the two are one"},
      {"LuGre", "Stribeck", false,
       "LuGre's friction in steady sliding is a Stribeck curve; what it adds is the bristles' memory"},
      {"BackDrive", "LoadFriction", false,
       "both add friction that grows with the motor's torque, BackDrive only while the load drives the gearbox "
       "backwards"},
      {"GravityLoadFriction", "LoadFriction", false,
       "both add friction that grows with the load, GravityLoadFriction with gravity's pull against the motor, on a "
       "limp servo too"},
      {"GravityLoadFriction", "BackDrive", false, "both brake a gearbox that the load drives backwards"},
      {"Backlash", "DeadBand", false,
       "both leave small moves unanswered, DeadBand in the controller, Backlash in the gears where the load turns"},
      {"Stribeck", "DeadBand", false, "both hold a joint still under a small error"},
      {"TransportDelay", "RotorInertia", false, "both make the joint lag behind its command"},
      {"TransportDelay", "Elasticity", false, "both make the joint lag behind its command"},
      {"RotorInertia", "Elasticity", false, "both slow the joint's response to a fast command"},
  };
  for (const EffectRelation& relation : relations) {
    if ((relation.first == a && relation.second == b) || (relation.first == b && relation.second == a)) {
      return &relation;
    }
  }
  return nullptr;
}

const EffectDescription* FindEffect(std::string_view name) {
  for (const EffectDescription& effect : EffectCatalogue()) {
    if (effect.name == name) return &effect;
  }
  return nullptr;
}

}  // namespace orcs::identify
