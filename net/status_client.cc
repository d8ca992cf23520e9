#include "net/status_client.h"

#include <google/protobuf/util/json_util.h>

#include <cstdio>

#include "net/envelope_check.h"
#include "proto/envelope.h"

namespace orcs::net {
namespace {

StatusClientOptions Checked(StatusClientOptions options) {
  if (options.endpoint.empty()) throw std::invalid_argument("StatusClient: empty broker endpoint");
  if (options.timeout.count() <= 0) throw std::invalid_argument("StatusClient: timeout must be positive");
  return options;
}

// The dealer's settings: a status client never heartbeats, so the interval only has to be valid.
DealerConnectionOptions DealerOptions(const StatusClientOptions& options) {
  struct {
    std::string endpoint;
    std::string curve_keys;
    std::chrono::milliseconds heartbeat_interval{1000};
    int liveness = 5;
  } side{options.endpoint, options.curve_keys};
  return DealerOptionsFor<v1::ClientToBroker>(side, "client", "StatusClient", [](const std::string&) {});
}

}  // namespace

StatusClient::StatusClient(StatusClientOptions options)
    : options_(Checked(std::move(options))), dealer_(DealerOptions(options_)) {}

v1::Status StatusClient::Fetch() {
  if (!dealer_.is_open()) dealer_.Open();
  v1::ClientToBroker request;
  request.set_protocol_version(proto::kProtocolVersion);
  request.mutable_status_request();
  dealer_.SendMessage(request);
  const auto deadline = DealerConnection::Clock::now() + options_.timeout;
  v1::Status status;
  while (DealerConnection::Clock::now() < deadline) {
    dealer_.Poll(deadline);
    if (ReadAnswer(status)) return status;
  }
  // A request that is still on its way would answer the next one: start over on a new connection instead.
  dealer_.Close();
  char seconds[32];
  std::snprintf(seconds, sizeof seconds, "%g s", std::chrono::duration<double>(options_.timeout).count());
  std::string message = "no broker answering at " + options_.endpoint + " after " + seconds;
  if (!dealer_.last_handshake_failure().empty()) message += " (" + dealer_.last_handshake_failure() + ")";
  throw StatusClientError(message + "; is orcs-broker running there (its first line names its client endpoint)?");
}

bool StatusClient::ReadAnswer(v1::Status& status) {
  bool answered = false;
  dealer_.ReceiveAll(
      [&](const zmq::message_t& frame) {
        if (!CheckEnvelope(frame, in_).empty()) return true;  // not for us: keep reading
        if (in_.body_case() != v1::BrokerToClient::kStatus) return true;
        status.Swap(in_.mutable_status());
        answered = true;
        return false;
      },
      [](const std::string&) {});
  return answered;
}

std::string StatusJson(const v1::Status& status) {
  google::protobuf::util::JsonPrintOptions options;
  options.always_print_primitive_fields = true;
  options.preserve_proto_field_names = true;
  std::string json;
  const auto written = google::protobuf::util::MessageToJsonString(status, &json, options);
  if (!written.ok()) throw std::runtime_error("cannot write the status as JSON: " + std::string(written.message()));
  return json;
}

}  // namespace orcs::net
