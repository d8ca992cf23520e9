// Posing an agent's joints: the kinematics behind the start-pose randomisation of the initial motor angles
// (docs/scenarios.md, "Randomisation"). Which bodies turn when a motorised hinge turns, about which line, and in
// which order, worked out on the compiled model alone; Simulation::SetAgentJointAngles applies it to the world.
//
// The agent's joints (its motors, its fixed joints and any joint holding one of its bodies to the static world)
// form a tree. Its root is the static world when such a holding joint exists (the holdBody test stand, the
// pendulum rig's motor clamped to its frame), else the morphology's root body (the A-Series pelvis,
// Middle/InvisiblePart, spec §4a). Posing keeps the root where it is and turns, for every hinge, the bodies on
// its far side from the root. Turning the hinges from the root outward composes nested limbs: a hinge's line
// has already been carried to where its parents put it.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "model/aseries/aseries_builder.h"
#include "model/aseries/aseries_morphology.h"
#include "model/physics/physics_model.h"
#include "model/physics/physics_world.h"

namespace orcs::scene {

/// One motorised hinge of an agent as posing sees it.
struct PosingJoint {
  int motor = -1;          ///< index in the agent's motor order (ASeriesLayout::motors)
  int joint = -1;          ///< physics joint index
  int proximal_body = -1;  ///< physics body on the root side of the hinge; -1 = the static world
  std::vector<int> distal_bodies;  ///< every physics body on the far side of the hinge (its whole subtree)
  /// +1 when the far side is the joint's body 1, −1 when it is body 2. ODE's convention: a hinge angle of +θ
  /// means body 1 has turned by +θ right-handedly about the axis relative to body 2 (spec §4c), so turning the
  /// far side by sign·Δ about the axis changes the angle by +Δ.
  double sign = 1.0;
};

/// A hinge's line in the world: a point on it and its direction.
struct HingeLine {
  Eigen::Vector3d anchor = Eigen::Vector3d::Zero();  ///< a point on the axis, world, m
  Eigen::Vector3d axis = Eigen::Vector3d::UnitX();   ///< unit direction, world
};

/// The root of agent `layout`'s tree: -1 (the static world) when one of the model's joints holds an agent body
/// to the world, else the physics index of `morphology.root_body`.
int PosingRoot(const physics::PhysicsModel& physics, const aseries::ASeriesLayout& layout,
               const aseries::ASeriesMorphology& morphology);

/// The agent's motorised hinges ordered from `root` outward (breadth-first): every hinge comes after the hinges
/// between it and the root. Each motor appears exactly once. Asserts that the agent's joints form a tree that
/// reaches every motor from `root`.
std::vector<PosingJoint> PosingOrder(const physics::PhysicsModel& physics, const aseries::ASeriesLayout& layout,
                                     int root);

/// Where `hinge`'s line is now: its initial-pose anchor and axis (the joint description) carried along with
/// its proximal body from that body's initial pose to `proximal` (ignored when the proximal side is the world).
HingeLine HingeLineNow(const physics::PhysicsModel& physics, const PosingJoint& hinge,
                       const physics::BodyState& proximal);

}  // namespace orcs::scene
