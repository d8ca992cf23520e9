// The ODCP 1.0 server (docs/spec/osp.md, docs/osp.md): direct, unsynchronised motor control of one agent
// over UDP, as the original's motion editors and slider tools spoke it. One server per agent. It owns a
// socket and answers each datagram at once to the address it came from:
//   5 (connect)      → 6, int 15, int 1
//   7 (disconnect)   → 8
//   100, 2N × int    set motors: N goal-angle words, then N torque words, each 0..1023; no reply
//   150 (get motors) → 151, 2N × int: N angle words, then the N torque words last set. The angles are the
//                      motors' angle sensors, as the original described it, or the goal angles last set, as the
//                      successor answers, with /SimpleUdpMotorInterface/ReportGoalAngles (protocol_values.h).
// A word w is n = −1 + 2w/1023; the goal angle is 150·n degrees (DesiredAngle, spec/aseries.md §4d) and the
// torque (n+1)/2 = w/1023 of the maximum, which is DesiredTorque's raw value (the motor uses max(0, raw) of its
// maximum torque). Words outside 0..1023 are clamped; a set-motors with another word count, an unknown
// command, a datagram over 1024 bytes are ignored (counted, the first one logged). Nothing crashes it.
//
// What the words drive is an OdcpMotors: the agent's repository values in a live simulation (AgentMotors),
// or a recorder (the KeyFrameSniffer). The server is served by whoever polls its socket: OspServer::AddService
// in orcs-osp, orcs-sim's real-time loop, orcs-sniffer.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "worker/osp/agent_interface.h"
#include "worker/osp/osp_server.h"
#include "worker/osp/udp_socket.h"

namespace orcs::osp {

/// ODCP command codes (the first byte of every datagram).
enum OdcpCommand : std::uint8_t {
  kOdcpConnect = 5,
  kOdcpConnectAck = 6,       ///< int 15, int 1
  kOdcpDisconnect = 7,
  kOdcpDisconnectAck = 8,
  kOdcpSetMotors = 100,      ///< 2N × int words
  kOdcpGetMotors = 150,
  kOdcpGetMotorsReply = 151, ///< 2N × int words
};

/// The two ints of the connect reply, as the successor sends them.
constexpr std::int32_t kOdcpConnectReplyFirst = 15;
constexpr std::int32_t kOdcpConnectReplySecond = 1;
/// The highest motor word.
constexpr std::int32_t kOdcpMaxWord = 1023;

/// The goal angle (degrees) of a word; words outside 0..1023 count as the nearest end.
double OdcpAngleOfWord(std::int32_t word);
/// The raw DesiredTorque (fraction of the maximum, 0…1) of a word; clamped like OdcpAngleOfWord.
double OdcpTorqueOfWord(std::int32_t word);
/// The nearest word of a goal angle (degrees); beyond ±150° gives 0 or 1023.
std::int32_t OdcpWordOfAngle(double degrees);
/// The nearest word of a raw DesiredTorque; a negative torque (no torque) gives 0, above 1 gives 1023.
std::int32_t OdcpWordOfTorque(double raw_torque);

/// What an ODCP server drives: the goal angles and torques of N motors, in raw units.
class OdcpMotors {
 public:
  virtual ~OdcpMotors() = default;
  virtual int motor_count() const = 0;
  /// The current goal angle (degrees) and raw DesiredTorque of motor `m`.
  virtual double angle(int m) const = 0;
  virtual double torque(int m) const = 0;
  /// The angle (degrees) get-motors reports for motor `m`: its angle sensor where there is one (the original's
  /// answer), else the goal angle.
  virtual double reported_angle(int m) const { return angle(m); }
  /// A set-motors command: one goal angle (degrees) and one raw torque (0…1) per motor.
  virtual void Set(std::span<const double> angles, std::span<const double> torques) = 0;
  /// A connect or a disconnect arrived (after its reply was sent).
  virtual void OnConnect() {}
  virtual void OnDisconnect() {}
};

/// An agent of a live simulation: set-motors writes its DesiredAngle and DesiredTorque repository values, which
/// the next simulation step uses (the caller steps in the same thread). Get-motors reports its JointAngle sensors,
/// or its goal angles while `report_goal_angles` (a repository bool, read at each request; nullptr = false) holds.
class AgentMotors : public OdcpMotors {
 public:
  explicit AgentMotors(AgentInterface agent, const Value* report_goal_angles = nullptr)
      : agent_(std::move(agent)), report_goal_angles_(report_goal_angles) {}
  int motor_count() const override { return static_cast<int>(agent_.inputs.size() / 2); }
  double angle(int m) const override { return agent_.inputs[2 * static_cast<std::size_t>(m)].value->as_double(); }
  double torque(int m) const override {
    return agent_.inputs[2 * static_cast<std::size_t>(m) + 1].value->as_double();
  }
  double reported_angle(int m) const override;
  void Set(std::span<const double> angles, std::span<const double> torques) override;
  const std::string& name() const { return agent_.name; }

 private:
  AgentInterface agent_;  // inputs: DesiredAngle, DesiredTorque per motor; outputs: JointAngle per motor first
  const Value* report_goal_angles_;  // the successor's answer while true
};

struct OdcpServerOptions {
  std::string bind_address = "127.0.0.1";  ///< interface to listen on; loopback unless told otherwise
  std::uint16_t port = 45453;              ///< /SimpleUdpMotorInterface/ServerPort; 0 = ephemeral
  std::string name = "odcp";               ///< what log lines start with, e.g. "ODCP Humanoid"
  /// Where log lines go (one event each, no newline); empty = stderr.
  std::function<void(std::string_view)> log;
};

/// Counters, for tests and logs; they only grow.
struct OdcpServerStats {
  std::uint64_t datagrams = 0;        ///< datagrams received
  std::uint64_t set_commands = 0;     ///< set-motors commands applied
  std::uint64_t words_clamped = 0;    ///< words outside 0..1023, clamped
  std::uint64_t datagrams_ignored = 0;  ///< wrong word count, unknown command, empty, oversized
};

class OdcpServer : public DatagramService {
 public:
  /// Binds the port; throws std::runtime_error naming the address when it cannot. `motors` must outlive it.
  OdcpServer(OdcpMotors& motors, OdcpServerOptions options);

  Endpoint endpoint() const { return socket_.local(); }
  const OdcpServerStats& stats() const { return stats_; }

  int fd() const override { return socket_.fd(); }
  /// Takes and answers every waiting datagram.
  void OnReadable() override;
  /// Answers one datagram (what OnReadable does with each; public for tests).
  void OnDatagram(const Datagram& datagram);

 private:
  void OnSetMotors(std::span<const std::uint8_t> words);
  void ReplyGetMotors(const Endpoint& to);
  void Reply(const std::vector<std::uint8_t>& bytes, const Endpoint& to);
  void Ignore(const std::string& why);
  void Log(const std::string& line) const;

  OdcpMotors& motors_;
  const OdcpServerOptions options_;
  UdpSocket socket_;
  OdcpServerStats stats_;
  bool warned_ = false;  // an ignored datagram was logged (further ones are only counted)
};

/// The ports of `agent_count` ODCP servers from `base`: base, base+1, ..., skipping `osp_port` (so that the default
/// base 45453 gives 45453, 45455, 45456, ... next to OSP's 45454). Base 0 gives 0 (ephemeral) for every agent.
/// Throws std::runtime_error when a port would exceed 65535.
std::vector<std::uint16_t> OdcpPorts(int base, int agent_count, int osp_port);

}  // namespace orcs::osp
