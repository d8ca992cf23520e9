#include "model/physics/ode/ode_joints.h"

namespace orcs::physics {
namespace {

// Bounce, soft ERP/CFM, slip in both friction directions, friction pyramid, separate μ2.
constexpr int kContactMode = dContactBounce | dContactSoftERP | dContactSoftCFM | dContactSlip1 | dContactSlip2 |
                             dContactApprox1 | dContactMu2;

}  // namespace

dJointID CreateFixedJoint(dWorldID world, dBodyID body1, dBodyID body2) {
  dJointID fixed = dJointCreateFixed(world, nullptr);
  dJointAttach(fixed, body1, body2);
  dJointSetFixed(fixed);  // keeps the current relative pose
  return fixed;
}

dJointID CreateHinge(dWorldID world, dBodyID body1, dBodyID body2, const JointDescription& joint) {
  dJointID hinge = dJointCreateHinge(world, nullptr);
  dJointAttach(hinge, body1, body2);
  dJointSetHingeAnchor(hinge, joint.anchor.x(), joint.anchor.y(), joint.anchor.z());
  dJointSetHingeAxis(hinge, joint.axis.x(), joint.axis.y(), joint.axis.z());
  if (joint.limited) {
    dJointSetHingeParam(hinge, dParamLoStop, joint.lo);
    dJointSetHingeParam(hinge, dParamHiStop, joint.hi);
  }
  dJointSetHingeParam(hinge, dParamVel, 0.0);
  dJointSetHingeParam(hinge, dParamFMax, 0.0);
  return hinge;
}

dJointID CreateContactJoint(dWorldID world, dJointGroupID group, const dContactGeom& point, dBodyID body1,
                            dBodyID body2, double mu, const ContactMaterial& material,
                            const PhysicsParameters& parameters) {
  dContact contact{};
  contact.surface.mode = kContactMode;
  contact.surface.mu = mu;
  contact.surface.mu2 = mu;
  contact.surface.bounce = material.restitution;
  contact.surface.bounce_vel = parameters.min_bouncing_velocity;
  contact.surface.soft_erp = parameters.soft_erp;
  contact.surface.soft_cfm = parameters.soft_cfm;
  contact.surface.slip1 = parameters.contact_slip;
  contact.surface.slip2 = parameters.contact_slip;
  contact.geom = point;
  dJointID joint = dJointCreateContact(world, group, &contact);
  dJointAttach(joint, body1, body2);
  return joint;
}

}  // namespace orcs::physics
