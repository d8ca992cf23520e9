// Watches one ZeroMQ socket for failed security handshakes (docs/security.md), so that a CURVE handshake that
// fails — a peer without CURVE, a key the broker refuses, a peer that trusts another broker key — is counted and
// explained instead of being a silent reconnection loop. The broker watches its two sockets; a worker or client
// watches its connection to say why the broker does not answer.
//
// Built on zmq_socket_monitor: the watched socket publishes its handshake events on an inproc PAIR socket, which
// the owner polls (socket()) on its own loop and drains with ReadFailures().
#pragma once

#include <cstdint>
#include <string>
#include <vector>
#include <zmq.hpp>

namespace orcs::net {

/// One failed handshake.
struct HandshakeFailure {
  std::uint16_t event = 0;  ///< ZMQ_EVENT_HANDSHAKE_FAILED_NO_DETAIL, _PROTOCOL or _AUTH
  std::int32_t value = 0;   ///< errno, ZMQ_PROTOCOL_ERROR_* code, or the ZAP status code (e.g. 400)
  /// Why, in words, e.g. "one side speaks CURVE and the other does not (mechanism mismatch)".
  std::string Describe() const;
  /// The connection closed before the handshake finished, without a reason: a peer without CURVE (as the broker
  /// sees it, when the peer notices first), but also a port scan or a peer checking an endpoint. Not a refusal.
  bool closed_early() const;
};

class HandshakeMonitor {
 public:
  /// Starts monitoring `watched` (a socket of `context`), publishing on "inproc://orcs-handshakes-<name>"; `name`
  /// must be unique among the monitors of `context`, over its lifetime (an endpoint is freed only lazily).
  /// Throws zmq::error_t when libzmq refuses.
  HandshakeMonitor(zmq::context_t& context, zmq::socket_t& watched, const std::string& name);
  /// Monitoring ends when `watched` closes; a monitor destroyed before that only stops reading the events.
  HandshakeMonitor(const HandshakeMonitor&) = delete;
  HandshakeMonitor& operator=(const HandshakeMonitor&) = delete;

  /// The socket to poll for ZMQ_POLLIN.
  zmq::socket_t& socket() { return socket_; }
  /// The failures reported since the last call, without blocking.
  std::vector<HandshakeFailure> ReadFailures();

 private:
  zmq::socket_t socket_;
};

}  // namespace orcs::net
