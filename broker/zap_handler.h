// The broker's ZeroMQ authentication handler (ZAP, rfc.zeromq.org/spec/27) for CURVE (docs/security.md).
// libzmq asks it, for every CURVE handshake on a socket of the same context, whether the peer's public key may
// connect; the request names the socket's ZAP domain, so a worker key is accepted on the worker socket only and a
// client key on the client socket only. A refused peer's connection is closed before any of its messages reaches
// the socket, so nothing it sends reaches the broker's handlers.
//
// Runs on the broker's poll loop (no thread of its own): the broker polls socket() and calls AnswerRequests().
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <set>
#include <string>
#include <string_view>
#include <zmq.hpp>

#include "net/curve_keys.h"

namespace orcs::broker {

/// Counters of a ZAP handler. Counters only grow.
struct ZapStats {
  std::uint64_t accepted = 0;  ///< handshakes whose key was allowed on the socket it knocked on
  std::uint64_t refused = 0;   ///< handshakes refused: unknown key, a key of the other role, or not CURVE
};

class ZapHandler {
 public:
  /// The endpoint libzmq sends ZAP requests to, fixed by the ZAP specification.
  static constexpr const char* kEndpoint = "inproc://zeromq.zap.01";

  /// Binds kEndpoint on `context`. `allowed` maps a ZAP domain (net::kWorkerZapDomain, ...) to the keys it
  /// accepts; a domain not in it accepts nothing. Construct before any CURVE server socket of `context` binds:
  /// without a handler libzmq lets every CURVE peer in. Throws std::runtime_error when kEndpoint is taken.
  ZapHandler(zmq::context_t& context, std::map<std::string, net::AllowedCurveKeys> allowed,
             std::function<void(const std::string&)> log);

  /// The socket to poll for ZMQ_POLLIN.
  zmq::socket_t& socket() { return socket_; }
  /// Answers every request waiting, without blocking.
  void AnswerRequests();
  const ZapStats& stats() const { return stats_; }

 private:
  /// Decides one request (the frames of the ZAP specification) and returns the reply's status code. An accepted
  /// key becomes `user_id` (Z85), which libzmq attaches to each of the peer's messages as "User-Id".
  std::string Decide(const std::vector<zmq::message_t>& request, std::string& user_id);
  void LogRefusal(const std::string& key, const std::string& line);

  zmq::socket_t socket_;
  std::map<std::string, net::AllowedCurveKeys> allowed_;
  std::function<void(const std::string&)> log_;
  std::set<std::string> warned_;  ///< refusals already logged (domain + key), bounded
  ZapStats stats_;
};

}  // namespace orcs::broker
