// The MuJoCo 2.2.2 backend of PhysicsWorld (Debian's libmujoco): the world compiled from the PhysicsModel through
// its generated MJCF (mjcf_export.h). Each world holds its own mjModel copy, because the per-run interface
// (motor limits, friction brakes, compliance, added inertia) writes model fields, and its own mjData.
//
// One step, as MuJoCo's mj_step but with the contacts rewritten between collision and constraint making:
// position stages → collide → per contact: drop shallow ones, mark excluded pairs, set the material table's
// friction (static while not sliding, else dynamic × scaling) → make constraints → velocity stages → mj_step2
// (actuation, acceleration, constraint solve, integration) → body kinematics of the new state → checks.
// A MuJoCo warning (bad qpos / qacc, contact or constraint buffer full, singular inertia) makes the step
// kEngineError with MuJoCo's own words; non-finite or too fast bodies make it kUnstable.
#pragma once

#include <memory>

#include "model/physics/physics_world.h"

namespace orcs::physics {

/// Creates a MuJoCo world for `model`. Throws InputError when MuJoCo cannot compile it (with MuJoCo's message)
/// or when its joints close a kinematic loop.
std::unique_ptr<PhysicsWorld> MakeMujocoWorld(std::shared_ptr<const PhysicsModel> model);

}  // namespace orcs::physics
