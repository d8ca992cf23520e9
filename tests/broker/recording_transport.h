// What the broker's core tests share (broker_core_test.cc, broker_state_table_test.cc): a transport that keeps
// every message BrokerCore sends, the owner token of every test batch, and a job by its id. No sockets.
#pragma once

#include <set>
#include <string>
#include <utility>
#include <vector>

#include "broker/broker_core.h"
#include "proto/envelope.h"

namespace orcs::test_support {

// The seam's test double: keeps every message the core sends, and fails sends to peers marked gone, as a ROUTER
// socket does once a peer's connection has closed.
class RecordingTransport final : public broker::BrokerTransport {
 public:
  bool SendToWorker(const std::string& worker, const v1::BrokerToWorker& message) override {
    if (gone.count(worker) != 0) return false;
    to_workers.emplace_back(worker, message);
    return true;
  }
  bool SendToClient(const std::string& client, const v1::BrokerToClient& message) override {
    if (gone.count(client) != 0) return false;
    to_clients.emplace_back(client, message);
    return true;
  }

  /// The JOBs sent to `worker`, in order.
  std::vector<v1::Job> Jobs(const std::string& worker) const {
    std::vector<v1::Job> jobs;
    for (const v1::BrokerToWorker& message : ToWorker(worker)) {
      if (message.has_job()) jobs.push_back(message.job());
    }
    return jobs;
  }
  /// Their job ids.
  std::vector<std::string> JobIds(const std::string& worker) const {
    std::vector<std::string> ids;
    for (const v1::Job& job : Jobs(worker)) ids.push_back(job.job_id());
    return ids;
  }
  /// The DISCONNECT reasons sent to `worker`, in order.
  std::vector<std::string> Disconnects(const std::string& worker) const {
    std::vector<std::string> reasons;
    for (const v1::BrokerToWorker& message : ToWorker(worker)) {
      if (message.has_disconnect()) reasons.push_back(message.disconnect().reason());
    }
    return reasons;
  }
  /// The REVOKEs sent to `worker`, in order.
  std::vector<v1::Revoke> Revokes(const std::string& worker) const {
    std::vector<v1::Revoke> revokes;
    for (const v1::BrokerToWorker& message : ToWorker(worker)) {
      if (message.has_revoke()) revokes.push_back(message.revoke());
    }
    return revokes;
  }
  /// The RESULTs sent to `client`, in order.
  std::vector<v1::Result> Results(const std::string& client) const {
    std::vector<v1::Result> results;
    for (const auto& [peer, message] : to_clients) {
      if (peer == client && message.has_result()) results.push_back(message.result());
    }
    return results;
  }
  /// The last message sent to `client` (empty when none).
  v1::BrokerToClient LastToClient(const std::string& client) const {
    for (auto entry = to_clients.rbegin(); entry != to_clients.rend(); ++entry) {
      if (entry->first == client) return entry->second;
    }
    return {};
  }
  /// The last message sent to `worker` (empty when none).
  v1::BrokerToWorker LastToWorker(const std::string& worker) const {
    const std::vector<v1::BrokerToWorker> messages = ToWorker(worker);
    return messages.empty() ? v1::BrokerToWorker{} : messages.back();
  }

  std::vector<std::pair<std::string, v1::BrokerToWorker>> to_workers;  ///< (routing id, message), in order
  std::vector<std::pair<std::string, v1::BrokerToClient>> to_clients;  ///< (routing id, message), in order
  std::set<std::string> gone;  ///< routing ids whose connection is closed: sends to them fail

 private:
  std::vector<v1::BrokerToWorker> ToWorker(const std::string& worker) const {
    std::vector<v1::BrokerToWorker> messages;
    for (const auto& [peer, message] : to_workers) {
      if (peer == worker) messages.push_back(message);
    }
    return messages;
  }
};

/// The owner token of every test batch.
inline const std::string kToken(16, '\x42');

/// A job with `id`, this protocol version, and a time limit (0 = none), s.
inline v1::Job Job(const std::string& id, double time_limit_seconds = 0) {
  v1::Job job;
  job.set_protocol_version(proto::kProtocolVersion);
  job.set_job_id(id);
  job.set_time_limit_seconds(time_limit_seconds);
  return job;
}

}  // namespace orcs::test_support
