// The ODCP 1.0 server fronting the physical robot (docs/hardware.md, "A motion editor on the robot"): a tool that
// speaks ODCP to the simulator — the original's MotionEditor, orcs-sniffer's editor side, a slider tool — drives
// the real robot unchanged. ODCP motor m is the joint map's joint m (the robot's motor order, as the simulator's
// agent numbers them). Set-motors gives each control period's commands, which go through the same limits as any
// other source's; get-motors answers the robot's measured angles (the original's answer: the angle sensors) and
// the torques last set. Before the first set-motors the robot holds the pose it was found in, at the map's torque
// limits. The session ends when the editor disconnects after a command, on Ctrl-C, or after its duration.
#pragma once

#include <string>
#include <vector>

#include "hardware/robot/command_source.h"
#include "hardware/robot/joint_map.h"
#include "worker/osp/odcp_server.h"

namespace orcs::hardware {

class OdcpSource final : public CommandSource, public osp::OdcpMotors {
 public:
  /// Binds the ODCP port (options.port; 0 = any). Throws InputError naming the address when it cannot. The server
  /// is served only from Commands(): nothing an editor sends acts outside the control loop.
  OdcpSource(const JointMap& map, osp::OdcpServerOptions options, double duration);

  osp::Endpoint endpoint() const { return server_.endpoint(); }
  const osp::OdcpServerStats& stats() const { return server_.stats(); }

  // CommandSource: the latest set-motors, polled once per control period.
  double duration() const override { return duration_; }
  bool finished() const override { return disconnected_; }
  void Commands(double time, const std::vector<double>& measured, std::vector<double>& goal,
                std::vector<double>& torque) override;

  // osp::OdcpMotors: what the server reads and writes.
  int motor_count() const override { return static_cast<int>(goal_.size()); }
  double angle(int m) const override { return goal_[static_cast<std::size_t>(m)]; }
  double torque(int m) const override { return torque_[static_cast<std::size_t>(m)]; }
  double reported_angle(int m) const override { return measured_[static_cast<std::size_t>(m)]; }
  void Set(std::span<const double> angles, std::span<const double> torques) override;
  void OnDisconnect() override { disconnected_ = disconnected_ || commanded_; }

  /// Set-motors commands taken so far.
  std::size_t commands() const { return commands_; }

 private:
  double duration_;               // s: the session's bound
  std::vector<double> goal_;      // per joint: the goal angle last set, degrees (the found pose before any)
  std::vector<double> torque_;    // per joint: the torque last set, 0…1 (the map's limit before any)
  std::vector<double> measured_;  // per joint: the robot's angles as last read, degrees (get-motors' answer)
  bool commanded_ = false;        // a set-motors arrived
  bool disconnected_ = false;     // the editor disconnected after a command: the session is over
  bool started_ = false;          // Commands() ran once (the found pose is known)
  std::size_t commands_ = 0;      // set-motors commands taken
  osp::OdcpServer server_;        // last: it reads the members above
};

}  // namespace orcs::hardware
