#include "model/physics/ode/ode_joints.h"

namespace orcs::physics {

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

}  // namespace orcs::physics
