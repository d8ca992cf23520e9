#include "worker/osp/odcp_server.h"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <stdexcept>

#include "model/aseries/value_range.h"
#include "worker/osp/osp_datagram.h"

namespace orcs::osp {
namespace {

// The normalised value n = −1 + 2w/1023 of a word, the word clamped to 0..1023 first.
double Normalised(std::int32_t word) {
  return -1.0 + 2.0 * static_cast<double>(std::clamp(word, 0, kOdcpMaxWord)) / kOdcpMaxWord;
}

// The nearest word of a normalised value, clamped to 0..1023 (NaN gives 0).
std::int32_t WordOfNormalised(double n) {
  const double word = std::round((n + 1.0) * kOdcpMaxWord / 2.0);
  if (!(word > 0.0)) return 0;
  return word >= kOdcpMaxWord ? kOdcpMaxWord : static_cast<std::int32_t>(word);
}

}  // namespace

double OdcpAngleOfWord(std::int32_t word) { return aseries::kDesiredAngleRange.ToRaw(Normalised(word)); }

double OdcpTorqueOfWord(std::int32_t word) { return (Normalised(word) + 1.0) / 2.0; }

std::int32_t OdcpWordOfAngle(double degrees) {
  return WordOfNormalised(aseries::kDesiredAngleRange.ToNormalised(degrees));
}

std::int32_t OdcpWordOfTorque(double raw_torque) { return WordOfNormalised(2.0 * raw_torque - 1.0); }

double AgentMotors::reported_angle(int m) const {
  if (report_goal_angles_ != nullptr && report_goal_angles_->as_bool()) return angle(m);
  return agent_.outputs[static_cast<std::size_t>(m)].value->as_double();  // the m-th output is its JointAngle
}

void AgentMotors::Set(std::span<const double> angles, std::span<const double> torques) {
  for (std::size_t m = 0; m < angles.size() && 2 * m + 1 < agent_.inputs.size(); ++m) {
    agent_.inputs[2 * m].value->Set(angles[m]);
    agent_.inputs[2 * m + 1].value->Set(torques[m]);
  }
}

OdcpServer::OdcpServer(OdcpMotors& motors, OdcpServerOptions options)
    : motors_(motors), options_(std::move(options)), socket_(options_.bind_address, options_.port) {}

void OdcpServer::Log(const std::string& line) const {
  if (options_.log) {
    options_.log(options_.name + ": " + line);
  } else {
    std::cerr << options_.name << ": " << line << "\n";
  }
}

void OdcpServer::OnReadable() {
  // Bounded: a sender flooding the port cannot keep this loop (and the simulation) from going on.
  for (int i = 0; i < 256; ++i) {
    std::optional<Datagram> datagram = socket_.Receive();
    if (!datagram) return;
    OnDatagram(*datagram);
  }
}

void OdcpServer::OnDatagram(const Datagram& datagram) {
  ++stats_.datagrams;
  if (datagram.truncated || datagram.bytes.size() > kMaxDatagramBytes) {
    return Ignore("a datagram longer than " + std::to_string(kMaxDatagramBytes) + " bytes from " +
                  datagram.from.ToString());
  }
  if (datagram.bytes.empty()) return Ignore("an empty datagram from " + datagram.from.ToString());
  const std::span<const std::uint8_t> rest = std::span(datagram.bytes).subspan(1);
  switch (datagram.bytes.front()) {
    case kOdcpConnect:
      Reply(DatagramWriter()
                .Byte(kOdcpConnectAck)
                .Int(kOdcpConnectReplyFirst)
                .Int(kOdcpConnectReplySecond)
                .Finish(false),
            datagram.from);
      return motors_.OnConnect();
    case kOdcpDisconnect:
      Reply(DatagramWriter().Byte(kOdcpDisconnectAck).Finish(false), datagram.from);
      return motors_.OnDisconnect();
    case kOdcpSetMotors: return OnSetMotors(rest);
    case kOdcpGetMotors: return ReplyGetMotors(datagram.from);
    default:
      return Ignore("unknown command " + std::to_string(datagram.bytes.front()) + " from " + datagram.from.ToString());
  }
}

void OdcpServer::OnSetMotors(std::span<const std::uint8_t> words) {
  const std::size_t motors = static_cast<std::size_t>(motors_.motor_count());
  if (words.size() != 8 * motors) {
    return Ignore("a set-motors command of " + std::to_string(words.size()) + " bytes; expected " +
                  std::to_string(2 * motors) + " words (" + std::to_string(8 * motors) + " bytes)");
  }
  DatagramReader reader(words);
  std::vector<double> angles(motors);
  std::vector<double> torques(motors);
  for (std::vector<double>* list : {&angles, &torques}) {
    for (double& raw : *list) {
      const std::int32_t word = reader.Int();
      if (word < 0 || word > kOdcpMaxWord) ++stats_.words_clamped;
      raw = list == &angles ? OdcpAngleOfWord(word) : OdcpTorqueOfWord(word);
    }
  }
  motors_.Set(angles, torques);
  ++stats_.set_commands;
}

void OdcpServer::ReplyGetMotors(const Endpoint& to) {
  DatagramWriter reply;
  reply.Byte(kOdcpGetMotorsReply);
  for (int m = 0; m < motors_.motor_count(); ++m) reply.Int(OdcpWordOfAngle(motors_.reported_angle(m)));
  for (int m = 0; m < motors_.motor_count(); ++m) reply.Int(OdcpWordOfTorque(motors_.torque(m)));
  try {
    Reply(reply.Finish(false), to);
  } catch (const MalformedDatagram& error) {  // more motors than a datagram carries
    Log("get-motors reply not sent: " + std::string(error.what()));
  }
}

void OdcpServer::Reply(const std::vector<std::uint8_t>& bytes, const Endpoint& to) {
  socket_.SendTo(bytes, to);  // a refused send (the sender has gone) is the sender's loss: ODCP guarantees nothing
}

void OdcpServer::Ignore(const std::string& why) {
  ++stats_.datagrams_ignored;
  if (warned_) return;  // one line: a flood of garbage must not flood the log
  warned_ = true;
  Log("ignored " + why + " (further ignored datagrams not logged)");
}

std::vector<std::uint16_t> OdcpPorts(int base, int agent_count, int osp_port) {
  std::vector<std::uint16_t> ports;
  int port = base;
  for (int a = 0; a < agent_count; ++a) {
    if (base == 0) {
      ports.push_back(0);
      continue;
    }
    if (port == osp_port) ++port;
    if (port > 65535) {
      throw std::runtime_error("ODCP port " + std::to_string(port) + " for agent " + std::to_string(a + 1) +
                               " exceeds 65535 (base port " + std::to_string(base) + ")");
    }
    ports.push_back(static_cast<std::uint16_t>(port++));
  }
  return ports;
}

}  // namespace orcs::osp
