#include "net/handshake_monitor.h"

#include <zmq.h>

#include <cstdio>
#include <cstring>
#include <iterator>
#include <zmq_addon.hpp>

namespace orcs::net {
namespace {

constexpr int kFailureEvents =
    ZMQ_EVENT_HANDSHAKE_FAILED_NO_DETAIL | ZMQ_EVENT_HANDSHAKE_FAILED_PROTOCOL | ZMQ_EVENT_HANDSHAKE_FAILED_AUTH;
constexpr std::size_t kEventFrameBytes = 6;  // uint16 event, uint32 value (libzmq's monitor format, version 1)
constexpr int kMaxEventsPerRound = 256;      // so that a flood of failures cannot starve the owner's loop

std::string Hex(std::int32_t value) {
  char text[16];
  std::snprintf(text, sizeof text, "0x%08x", static_cast<unsigned>(value));
  return text;
}

}  // namespace

bool HandshakeFailure::closed_early() const { return event == ZMQ_EVENT_HANDSHAKE_FAILED_NO_DETAIL; }

std::string HandshakeFailure::Describe() const {
  if (event == ZMQ_EVENT_HANDSHAKE_FAILED_AUTH) {
    return "the key was refused (authentication status " + std::to_string(value) + ")";
  }
  if (event == ZMQ_EVENT_HANDSHAKE_FAILED_PROTOCOL) {
    switch (value) {
      case ZMQ_PROTOCOL_ERROR_ZMTP_MECHANISM_MISMATCH:
        return "one side speaks CURVE and the other does not (mechanism mismatch)";
      case ZMQ_PROTOCOL_ERROR_ZMTP_CRYPTOGRAPHIC:
        return "the CURVE handshake did not decrypt (the client trusts another broker key?)";
      default: return "protocol error " + Hex(value);
    }
  }
  return std::string("the connection closed during the handshake (") + std::strerror(value) + ")";
}

HandshakeMonitor::HandshakeMonitor(zmq::context_t& context, zmq::socket_t& watched, const std::string& name)
    : socket_(context, zmq::socket_type::pair) {
  const std::string endpoint = "inproc://orcs-handshakes-" + name;
  if (zmq_socket_monitor(watched.handle(), endpoint.c_str(), kFailureEvents) != 0) throw zmq::error_t();
  socket_.set(zmq::sockopt::linger, 0);
  socket_.connect(endpoint);
}

std::vector<HandshakeFailure> HandshakeMonitor::ReadFailures() {
  std::vector<HandshakeFailure> failures;
  std::vector<zmq::message_t> frames;
  for (int i = 0; i < kMaxEventsPerRound; ++i) {
    frames.clear();
    if (!zmq::recv_multipart(socket_, std::back_inserter(frames), zmq::recv_flags::dontwait)) break;
    if (frames.empty() || frames[0].size() != kEventFrameBytes) continue;
    HandshakeFailure failure;
    std::memcpy(&failure.event, frames[0].data(), sizeof failure.event);
    std::memcpy(&failure.value, static_cast<const char*>(frames[0].data()) + sizeof failure.event,
                sizeof failure.value);
    if ((failure.event & kFailureEvents) != 0) failures.push_back(failure);
  }
  return failures;
}

}  // namespace orcs::net
