// Asks a broker what it is doing (docs/protocol.md, "Status"): one STATUS_REQUEST on a fresh client connection,
// one STATUS back. Used by `orcs-broker status`, by orcs-batch's "no worker is connected" hint and by orcs-view's
// dashboard — here in net/, the layer all three may use (docs/architecture.md), rather than in broker/. A status client registers nothing at the broker and sends no heartbeats; it keeps its connection
// open between requests, so a dashboard polling once a second opens one connection, not one a second.
#pragma once

#include <chrono>
#include <stdexcept>
#include <string>

#include "net/dealer_connection.h"
#include "orcs/v1/broker.pb.h"
#include "orcs/v1/status.pb.h"

namespace orcs::net {

struct StatusClientOptions {
  /// The broker's client endpoint, e.g. "tcp://127.0.0.1:5555".
  std::string endpoint;
  /// Folder of CURVE keys (docs/security.md), as for a batch client; "" = plain TCP. With CURVE the status shows
  /// the names and jobs of this key's batches only.
  std::string curve_keys;
  /// How long one Fetch() waits for the answer.
  std::chrono::milliseconds timeout{3000};
};

/// No answer in time, or a broker that refused the connection.
class StatusClientError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// One connection for status requests. Not thread-safe: one caller at a time.
class StatusClient {
 public:
  /// Throws std::invalid_argument for an empty endpoint or one ZeroMQ cannot parse, a non-positive timeout;
  /// net::CurveKeyError naming the file for a missing or malformed key.
  explicit StatusClient(StatusClientOptions options);
  StatusClient(const StatusClient&) = delete;
  StatusClient& operator=(const StatusClient&) = delete;

  /// The broker's status now. Throws StatusClientError "no broker answering at ENDPOINT after 3 s" (and why,
  /// when a CURVE handshake failed); the next call then starts on a new connection.
  v1::Status Fetch();

  const std::string& endpoint() const { return options_.endpoint; }
  const std::string& curve_keys() const { return options_.curve_keys; }

 private:
  /// Reads what waits on the socket; true when it held the answer, moved into `status`.
  bool ReadAnswer(v1::Status& status);

  const StatusClientOptions options_;
  net::DealerConnection dealer_;  ///< opened on the first Fetch(), reopened after a timeout
  v1::BrokerToClient in_;         ///< the message being read, reused
};

/// The status as one JSON object: protobuf's JSON mapping, every field present (zeros and empty lists too),
/// snake_case names as in status.proto. (`orcs-broker status --json`, orcs-view's /api/broker/status.)
std::string StatusJson(const v1::Status& status);

}  // namespace orcs::net
