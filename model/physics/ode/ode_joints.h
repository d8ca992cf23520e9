// ODE joints from a JointDescription: what OdeWorld builds, and what the raw-ODE peer in tests/bench/ builds to
// measure the physics layer against (the same joints, so that the comparison is fair).
#pragma once

#include <ode/ode.h>

#include "model/physics/physics_description.h"

namespace orcs::physics {

/// A fixed joint holding body2 (nullptr = the static world) in its current pose relative to body1.
dJointID CreateFixedJoint(dWorldID world, dBodyID body1, dBodyID body2);

/// `joint`'s hinge between body1 and body2 (nullptr = the static world): anchor, axis and, when limited, its
/// stops. The hinge's own motor is off (velocity 0, no force): callers that brake or hold with it set dParamFMax.
dJointID CreateHinge(dWorldID world, dBodyID body1, dBodyID body2, const JointDescription& joint);

}  // namespace orcs::physics
