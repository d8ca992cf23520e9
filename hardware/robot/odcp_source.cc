#include "hardware/robot/odcp_source.h"

#include <stdexcept>

#include "model/core/error.h"

namespace orcs::hardware {
namespace {

osp::OdcpServer BindServer(osp::OdcpMotors& motors, osp::OdcpServerOptions options) {
  const std::string where = options.bind_address + ":" + std::to_string(options.port);
  try {
    return osp::OdcpServer(motors, std::move(options));
  } catch (const std::runtime_error& error) {  // a port in use, an address that cannot be bound: the user's to fix
    throw InputError("--odcp: cannot listen on " + where + ": " + error.what());
  }
}

}  // namespace

OdcpSource::OdcpSource(const JointMap& map, osp::OdcpServerOptions options, double duration)
    : duration_(duration),
      goal_(map.joints.size(), 0.0),
      torque_(),
      measured_(map.joints.size(), 0.0),
      server_(BindServer(*this, std::move(options))) {
  for (const JointMapping& joint : map.joints) torque_.push_back(joint.max_torque);
}

void OdcpSource::Commands(double, const std::vector<double>& measured, std::vector<double>& goal,
                          std::vector<double>& torque) {
  measured_ = measured;
  if (!started_ && !commanded_) goal_ = measured;  // hold the pose the robot was found in
  started_ = true;
  server_.OnReadable();  // every datagram waiting, bounded; answers get-motors with `measured`
  goal = goal_;
  torque = torque_;
}

void OdcpSource::Set(std::span<const double> angles, std::span<const double> torques) {
  goal_.assign(angles.begin(), angles.end());
  torque_.assign(torques.begin(), torques.end());
  commanded_ = true;
  ++commands_;
}

}  // namespace orcs::hardware
