// The ODE joints OdeWorld creates — hinges, fixed joints, contacts — as functions, so that the raw-ODE peer in
// tests/bench/ builds exactly the same ones and the comparison measures the physics layer, not different joints.
#pragma once

#include <ode/ode.h>

#include "model/physics/material_table.h"
#include "model/physics/physics_description.h"
#include "model/physics/physics_parameters.h"

namespace orcs::physics {

/// A fixed joint holding body2 (nullptr = the static world) in its current pose relative to body1.
dJointID CreateFixedJoint(dWorldID world, dBodyID body1, dBodyID body2);

/// `joint`'s hinge between body1 and body2 (nullptr = the static world): anchor, axis and, when limited, its
/// stops. The hinge's own motor is off (velocity 0, no force): callers that brake or hold with it set dParamFMax.
dJointID CreateHinge(dWorldID world, dBodyID body1, dBodyID body2, const JointDescription& joint);

/// A contact joint in `group` at `point` between body1 and body2 (either nullptr = the static world), with the
/// contact surface of every contact (spec/aseries.md §8): friction `mu` in both directions (a pyramid), the
/// material's restitution, the soft ERP/CFM, bounce velocity and slip of `parameters`.
dJointID CreateContactJoint(dWorldID world, dJointGroupID group, const dContactGeom& point, dBodyID body1,
                            dBodyID body2, double mu, const ContactMaterial& material,
                            const PhysicsParameters& parameters);

}  // namespace orcs::physics
