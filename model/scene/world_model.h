// The compiled world (MuJoCo's mjModel layer): an environment turned into a checked physics model, with the
// mapping from environment objects to physics bodies. Immutable; one model serves any number of simulations.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "model/aseries/aseries_builder.h"
#include "model/core/variable_repository.h"
#include "model/physics/physics_model.h"
#include "model/scene/environment_description.h"

namespace orcs::scene {

class WorldModel {
 public:
  /// Compiles `environment`. Object properties are read from `values` (the /Sim/<object>/... values that
  /// RegisterObjectValues created, possibly changed by -ival files), so initial value files can move, resize
  /// or re-weigh objects before the world is built. Throws InputError for inconsistent values.
  static std::shared_ptr<const WorldModel> Compile(const EnvironmentDescription& environment,
                                                   const VariableRepository& values);

  /// Registers /Sim/<object>/... values (Position, Orientation, OrientationQuaternion, Mass, Material, Color,
  /// Texture, Dynamic, Width/Height/Depth or Radius, StaticFriction, DynamicFriction, Elasticity) for every
  /// object, /Sim/Floor/Material, and /Sim/<agent>/<body>/Position, Orientation, OrientationQuaternion for every
  /// body of every agent, and every agent's morphology values (model/aseries/morphology_values.h), with the
  /// description's values.
  static void RegisterObjectValues(const EnvironmentDescription& environment, VariableRepository& values);

  /// One structure value the model was compiled from: a /Sim/... value read only at compile time (an object's
  /// Mass, Material, size, start pose, ...; the floor's material; a robot body's Mass, size, Material, Color; a
  /// hinge's stops, model/aseries/morphology_values.h). Simulation recompiles at a reset when one has changed.
  struct StructureValue {
    std::string path;  ///< repository path
    std::string text;  ///< its value when compiled, as Value::ToString prints it
    /// true for an object's Position and Orientation: the physics publishes the moving pose there, so only a
    /// write from outside (not the published pose) is a new start pose.
    bool pose = false;
  };

  /// The structure values' paths of `environment` (those RegisterObjectValues creates, less the published pose
  /// of the robots' bodies and the objects' OrientationQuaternion), with `text` empty.
  static std::vector<StructureValue> StructurePaths(const EnvironmentDescription& environment);

  const EnvironmentDescription& environment() const { return environment_; }
  /// The structure values as compiled, in StructurePaths order.
  const std::vector<StructureValue>& structure() const { return structure_; }
  const std::shared_ptr<const physics::PhysicsModel>& physics() const { return physics_; }
  /// Name used in repository paths and events for a body (the object name, "Floor" for the floor).
  const std::string& body_name(int body) const { return physics_->body(body).name; }
  /// Where each agent of the environment went in the physics model, in environment order.
  const std::vector<aseries::ASeriesLayout>& agents() const { return agents_; }
  /// Agent `index`'s morphology: the A-Series or a pendulum rig built from its attributes, with the agent's
  /// morphology values (/Sim/<agent>/<body>/Mass, ...) applied.
  const aseries::ASeriesMorphology& morphology(int index) const { return *morphologies_[index]; }

  /// The morphology an agent description asks for, before its values apply (shared: the A-Series one is built
  /// once per process).
  static std::shared_ptr<const aseries::ASeriesMorphology> MorphologyOf(const AgentDescription& agent);

 private:
  WorldModel() = default;

  EnvironmentDescription environment_;
  std::shared_ptr<const physics::PhysicsModel> physics_;
  std::vector<aseries::ASeriesLayout> agents_;
  std::vector<std::shared_ptr<const aseries::ASeriesMorphology>> morphologies_;  // per agent, values applied
  std::vector<StructureValue> structure_;
};

}  // namespace orcs::scene
