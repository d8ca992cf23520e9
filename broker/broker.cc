#include "broker/broker.h"

#include <sys/eventfd.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <iterator>
#include <optional>
#include <stdexcept>
#include <vector>
#include <zmq_addon.hpp>

#include "proto/envelope.h"
#include "proto/secure_random.h"

namespace orcs::broker {
namespace {

using proto::kProtocolVersion;

constexpr std::uint32_t kMaxCredit = 1024;          // most jobs one worker may hold (Ready.credit)
constexpr std::int64_t kMaxMessageBytes = 1 << 29;  // 512 MiB: larger messages close the sender's connection
constexpr int kMaxMessagesPerRound = 256;           // per socket and loop iteration, so neither side starves
constexpr int kCloseLingerMs = 200;                 // how long DISCONNECTs may take to leave when closing
constexpr std::size_t kMaxWarnedPeers = 4096;       // bound on the "logged once" set
constexpr std::size_t kMaxIdBytes = 128;            // worker, client and batch ids (a longer one is refused)
constexpr std::size_t kMaxJobIdBytes = 256;         // job ids
constexpr std::size_t kMinOwnerTokenBytes = 16;     // Submit.owner_token: at least 128 bits
constexpr std::size_t kMaxOwnerTokenBytes = 64;
constexpr std::size_t kMaxLogLine = 2000;           // bytes of one log line, escapes included
// A lease lasts the job's time limit × 1.5 + 2 s, plus the liveness period: longer than the worker's own watch
// (limit + 1 s + 25 %, docs/protocol.md "Crash isolation"), so a working worker reports TIMEOUT first.
constexpr double kLeaseFactor = 1.5;
constexpr double kLeaseMarginSeconds = 2.0;

// The line with control characters and invalid bytes as \xNN, cut at kMaxLogLine bytes.
std::string EscapeForLog(std::string_view line) {
  static constexpr char kDigits[] = "0123456789abcdef";
  std::string text;
  text.reserve(std::min(line.size(), kMaxLogLine));
  for (unsigned char c : line) {
    if (text.size() >= kMaxLogLine) {
      text += "... (cut)";
      break;
    }
    if (c < 0x20 || c == 0x7f || c == '\\') {
      text += "\\x";
      text += kDigits[c >> 4];
      text += kDigits[c & 0xf];
    } else {
      text += static_cast<char>(c);
    }
  }
  return text;
}

// Compares two secrets in time that does not depend on where they differ.
bool SameSecret(const std::string& a, const std::string& b) {
  if (a.size() != b.size()) return false;
  unsigned char difference = 0;
  for (std::size_t i = 0; i < a.size(); ++i) difference |= static_cast<unsigned char>(a[i] ^ b[i]);
  return difference == 0;
}

// "0x0080000001": a routing id for the log.
std::string Hex(const std::string& bytes) {
  static constexpr char kDigits[] = "0123456789abcdef";
  std::string text = "0x";
  for (unsigned char c : bytes) {
    text += kDigits[c >> 4];
    text += kDigits[c & 0xf];
  }
  return text;
}

std::string Seconds(std::chrono::steady_clock::duration duration) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f s", std::chrono::duration<double>(duration).count());
  return text;
}

double SecondsBetween(std::chrono::steady_clock::time_point from, std::chrono::steady_clock::time_point to) {
  return std::chrono::duration<double>(to - from).count();
}

void Configure(zmq::socket_t& socket) {
  socket.set(zmq::sockopt::router_mandatory, 1);  // a send to a vanished peer fails instead of vanishing
  socket.set(zmq::sockopt::sndhwm, 0);            // never drop a message to a slow peer: results must arrive
  socket.set(zmq::sockopt::rcvhwm, 0);            // never make a peer block on us
  socket.set(zmq::sockopt::maxmsgsize, kMaxMessageBytes);
  socket.set(zmq::sockopt::linger, kCloseLingerMs);
}

// Binds `socket` and returns the endpoint it got (with the real port when 0 was asked for).
std::string Bind(zmq::socket_t& socket, const std::string& address, int port, const std::string& what) {
  const std::string endpoint = "tcp://" + address + ":" + (port == 0 ? std::string("*") : std::to_string(port));
  try {
    socket.bind(endpoint);
  } catch (const zmq::error_t& error) {
    throw std::runtime_error("cannot bind the " + what + " socket to " + endpoint + ": " + error.what());
  }
  return socket.get(zmq::sockopt::last_endpoint);
}

void Validate(const BrokerOptions& options) {
  if (options.bind_address.empty()) throw std::invalid_argument("empty bind address");
  for (int port : {options.client_port, options.worker_port}) {
    if (port < 0 || port > 65535) throw std::invalid_argument("port " + std::to_string(port) + " outside 0..65535");
  }
  if (options.heartbeat_interval.count() <= 0) throw std::invalid_argument("heartbeat interval must be positive");
  if (options.liveness < 2) throw std::invalid_argument("liveness must be at least 2 heartbeat intervals");
  if (options.max_worker_losses < 1) throw std::invalid_argument("max_worker_losses must be at least 1");
  if (options.max_crashes < 1) throw std::invalid_argument("max_crashes must be at least 1");
  if (!(options.default_time_limit_seconds > 0) || options.default_time_limit_seconds > 1e7) {
    throw std::invalid_argument("default time limit must be within (0, 1e7] s");
  }
}

}  // namespace

Broker::Broker(BrokerOptions options)
    : options_((Validate(options), std::move(options))),
      liveness_period_(options_.heartbeat_interval * options_.liveness),
      context_(1),
      client_socket_(context_, zmq::socket_type::router),
      worker_socket_(context_, zmq::socket_type::router) {
  Configure(client_socket_);
  Configure(worker_socket_);
  if (!options_.curve_keys.empty()) EnableCurve();
  client_endpoint_ = Bind(client_socket_, options_.bind_address, options_.client_port, "client");
  worker_endpoint_ = Bind(worker_socket_, options_.bind_address, options_.worker_port, "worker");
  wake_fd_ = ::eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
  if (wake_fd_ < 0) throw std::runtime_error("eventfd failed");
  if (!options_.journal.empty()) {
    journal_ = std::make_unique<BrokerJournal>(options_.journal);
    Restore();
  }
}

void Broker::EnableCurve() {
  const net::CurveBrokerKeys keys = net::LoadCurveBrokerKeys(options_.curve_keys);
  // The handler first: a CURVE server socket of a context without one lets every key in.
  zap_ = std::make_unique<ZapHandler>(
      context_,
      std::map<std::string, net::AllowedCurveKeys>{{net::kWorkerZapDomain, keys.allowed_workers},
                                                     {net::kClientZapDomain, keys.allowed_clients}},
      [this](const std::string& line) { Log(line); });
  net::MakeCurveServer(client_socket_, keys.own, net::kClientZapDomain);
  net::MakeCurveServer(worker_socket_, keys.own, net::kWorkerZapDomain);
  client_monitor_ = std::make_unique<net::HandshakeMonitor>(context_, client_socket_, "client");
  worker_monitor_ = std::make_unique<net::HandshakeMonitor>(context_, worker_socket_, "worker");
  Log("CURVE on (keys in " + options_.curve_keys + "): " + std::to_string(keys.allowed_workers.size()) +
      " worker keys and " + std::to_string(keys.allowed_clients.size()) + " client keys allowed");
}

void Broker::ReadHandshakeFailures(net::HandshakeMonitor& monitor, const std::string& side) {
  for (const net::HandshakeFailure& failure : monitor.ReadFailures()) {
    ++counters_.handshakes_failed;
    // Refusals are logged by the ZAP handler, with the key; early closes are routine (scans, endpoint checks).
    if (failure.event == ZMQ_EVENT_HANDSHAKE_FAILED_AUTH || failure.closed_early()) continue;
    const std::string why = failure.Describe();
    if (warned_handshakes_.size() < kMaxWarnedPeers && warned_handshakes_.insert(side + why).second) {
      Log("a " + side + " connection failed its handshake: " + why + " (logged once per kind)");
    }
  }
}

Broker::~Broker() {
  client_socket_.close();
  worker_socket_.close();
  if (wake_fd_ >= 0) ::close(wake_fd_);
}

void Broker::Stop() {
  stop_requested_.store(true);
  const std::uint64_t one = 1;
  [[maybe_unused]] const ssize_t written = ::write(wake_fd_, &one, sizeof one);
}

BrokerStats Broker::stats() const {
  std::lock_guard lock(stats_mutex_);
  return stats_;
}

void Broker::Run() {
  if (ran_) throw std::logic_error("Broker::Run called twice");
  ran_ = true;
  now_ = Clock::now();
  Clock::time_point next_tick = now_ + options_.heartbeat_interval;
  std::vector<zmq::pollitem_t> items = {{worker_socket_.handle(), 0, ZMQ_POLLIN, 0},
                                       {client_socket_.handle(), 0, ZMQ_POLLIN, 0},
                                       {nullptr, wake_fd_, ZMQ_POLLIN, 0}};
  if (zap_) {  // items 3, 4, 5
    items.push_back({zap_->socket().handle(), 0, ZMQ_POLLIN, 0});
    items.push_back({client_monitor_->socket().handle(), 0, ZMQ_POLLIN, 0});
    items.push_back({worker_monitor_->socket().handle(), 0, ZMQ_POLLIN, 0});
  }
  PublishStats();
  while (!stop_requested_.load()) {
    const auto wait =
        std::chrono::ceil<std::chrono::milliseconds>(std::max(next_tick - Clock::now(), Clock::duration{}));
    try {
      zmq::poll(items, wait);
    } catch (const zmq::error_t& error) {
      if (error.num() != EINTR) throw;
      continue;  // a signal (orcs-broker's SIGTERM handler calls Stop())
    }
    if (items[2].revents & ZMQ_POLLIN) {
      std::uint64_t count = 0;
      [[maybe_unused]] const ssize_t read = ::read(wake_fd_, &count, sizeof count);
    }
    if (stop_requested_.load()) break;
    if (zap_) {
      if (items[3].revents & ZMQ_POLLIN) zap_->AnswerRequests();
      if (items[4].revents & ZMQ_POLLIN) ReadHandshakeFailures(*client_monitor_, "client");
      if (items[5].revents & ZMQ_POLLIN) ReadHandshakeFailures(*worker_monitor_, "worker");
    }
    if (journal_) journal_->Begin();  // one transaction per turn: what this turn changed lands together
    now_ = Clock::now();
    if (items[0].revents & ZMQ_POLLIN) ReceiveWorkerMessages();
    if (items[1].revents & ZMQ_POLLIN) ReceiveClientMessages();
    now_ = Clock::now();
    if (now_ >= next_tick) {
      OnTick(now_);
      next_tick = now_ + options_.heartbeat_interval;
    }
    Dispatch();
    if (journal_) journal_->Commit();
    PublishStats();
  }
  SayGoodbye();
  PublishStats();
  client_socket_.close();
  worker_socket_.close();
}

// ---------------------------------------------------------------------------------------------------------------
// Incoming traffic

void Broker::ReceiveWorkerMessages() {
  for (int i = 0; i < kMaxMessagesPerRound; ++i) {
    frames_.clear();
    if (!zmq::recv_multipart(worker_socket_, std::back_inserter(frames_), zmq::recv_flags::dontwait)) return;
    const std::string worker = frames_[0].to_string();
    if (frames_.size() != 2) {
      DropMessage("worker", worker, "expected one frame, got " + std::to_string(frames_.size() - 1));
      continue;
    }
    OnWorkerMessage(worker, frames_[1]);
  }
}

void Broker::ReceiveClientMessages() {
  for (int i = 0; i < kMaxMessagesPerRound; ++i) {
    frames_.clear();
    if (!zmq::recv_multipart(client_socket_, std::back_inserter(frames_), zmq::recv_flags::dontwait)) return;
    const std::string client = frames_[0].to_string();
    if (frames_.size() != 2) {
      DropMessage("client", client, "expected one frame, got " + std::to_string(frames_.size() - 1));
      continue;
    }
    // With CURVE, the ZAP handler named the sender's key as its User-Id: the key a batch belongs to.
    const char* key = zap_ ? zmq_msg_gets(frames_[1].handle(), "User-Id") : nullptr;
    client_key_ = key != nullptr ? key : "";
    OnClientMessage(client, frames_[1]);
  }
}

void Broker::OnWorkerMessage(const std::string& worker, zmq::message_t& payload) {
  const proto::EnvelopeCheck check = proto::ParseEnvelope(payload.data(), payload.size(), worker_in_);
  if (check != proto::EnvelopeCheck::kOk) {
    std::string why(proto::Describe(check));
    if (check == proto::EnvelopeCheck::kWrongVersion) {
      why +=
          " " + std::to_string(worker_in_.protocol_version()) + " (expected " + std::to_string(kProtocolVersion) + ")";
    }
    DropMessage("worker", worker, why);
    return;
  }
  auto known = workers_.find(worker);
  if (known != workers_.end()) known->second.expiry = now_ + liveness_period_;
  switch (worker_in_.body_case()) {
    case v1::WorkerToBroker::kReady: OnWorkerReady(worker, worker_in_.ready()); break;
    case v1::WorkerToBroker::kResult: OnWorkerResult(worker, *worker_in_.mutable_result()); break;
    case v1::WorkerToBroker::kHeartbeat: OnWorkerHeartbeat(worker); break;
    case v1::WorkerToBroker::kDisconnect: OnWorkerDisconnect(worker, worker_in_.disconnect()); break;
    case v1::WorkerToBroker::BODY_NOT_SET: break;  // ParseEnvelope rejected it already
  }
}

void Broker::OnWorkerReady(const std::string& worker, const v1::Ready& ready) {
  if (ready.credit() < 1 || ready.credit() > kMaxCredit) {
    DropMessage(
        "worker", worker,
        "READY with credit " + std::to_string(ready.credit()) + " (expected 1.." + std::to_string(kMaxCredit) + ")");
    return;
  }
  if (ready.worker_id().size() > kMaxIdBytes) {
    DropMessage("worker", worker,
                "READY with a worker_id of " + std::to_string(ready.worker_id().size()) + " bytes (at most " +
                    std::to_string(kMaxIdBytes) + ")");
    return;
  }
  auto [entry, inserted] = workers_.try_emplace(worker);
  Worker& record = entry->second;
  record.name = ready.worker_id().empty() ? Hex(worker) : ready.worker_id();
  record.credit = ready.credit();
  record.expiry = now_ + liveness_period_;
  Log((inserted ? "worker " + record.name + " joined with credit "
                : "worker " + record.name + " sent READY again; credit now ") +
      std::to_string(record.credit));
  MakeReady(worker, record);
}

void Broker::OnWorkerResult(const std::string& worker, v1::Result& result) {
  if (result.protocol_version() != kProtocolVersion) {
    DropMessage("worker", worker, "RESULT with protocol version " + std::to_string(result.protocol_version()));
    return;
  }
  const JobKey key{result.batch_id(), result.job_id()};
  JobRecord* record = FindJob(key);
  const std::string problem = LeaseProblem(worker, result, record);
  if (!problem.empty()) {
    RefuseResult(worker, result, problem);
    return;
  }
  // The answer to the lease this connection holds: one credit back, and the job ends or is retried.
  Worker& holder = workers_.at(worker);
  in_flight_count_ -= holder.holding.erase(key);
  if (holder.holding.empty()) holder.busy_until = now_;
  MakeReady(worker, holder);
  record->lease = 0;
  if (result.worker_id().empty()) result.set_worker_id(holder.name);
  Batch& batch = batches_.at(key.first);
  if (result.status() == v1::Result::CRASHED) {
    OnJobCrashed(worker, key.first, batch, *record, result);
  } else {
    FinishJob(batch, *record, result);
  }
}

std::string Broker::LeaseProblem(const std::string& worker, const v1::Result& result, const JobRecord* record) const {
  if (workers_.count(worker) == 0) return "from a connection that never sent READY (or was declared lost)";
  if (record == nullptr) return "for a job the broker does not know (its batch ended or never existed)";
  if (record->state == JobState::kFinished) return "for a job that has its result already";
  if (record->state != JobState::kDispatched || record->worker != worker) {
    return "for a job not leased to this connection";
  }
  if (result.lease() != record->lease) return "without the token of the job's current lease";
  return "";
}

// A result is accepted only from the connection holding the job's current lease, with its token: a peer cannot
// finish a job it was not given, nor a worker a job that has gone elsewhere since. The rest is counted and logged
// (once per peer: a flood of forgeries makes one line).
void Broker::RefuseResult(const std::string& worker, const v1::Result& result, const std::string& why) {
  ++counters_.results_refused;
  if (warned_peers_.size() >= kMaxWarnedPeers) warned_peers_.clear();
  if (warned_peers_.insert("refused" + worker).second) {
    Log("refused a result " + why + ": job " + result.batch_id() + "/" + result.job_id() + " from worker " +
        WorkerName(worker) + " (further refused results from this peer are counted without a log line)");
  }
  if (workers_.count(worker) == 0) {
    v1::BrokerToWorker reply;
    reply.set_protocol_version(kProtocolVersion);
    reply.mutable_disconnect()->set_reason("unknown worker: connect again and send READY");
    SendToWorker(worker, reply);
  }
}

void Broker::OnJobCrashed(const std::string& worker, const std::string& batch_id, Batch& batch, JobRecord& record,
                          v1::Result& result) {
  ++counters_.crashes;
  ++record.crashes;
  const std::string name = result.worker_id().empty() ? WorkerName(worker) : result.worker_id();
  record.crashed_by += (record.crashed_by.empty() ? "" : ", ") + name;
  const std::string job = batch_id + "/" + record.job.job_id();
  if (record.crashes >= options_.max_crashes) {
    ++counters_.jobs_poisoned;
    const std::string poisonous =
        "poisonous: crashed " + std::to_string(record.crashes) + " workers (" + record.crashed_by + ")";
    Log("job " + job + " " + poisonous + "; not retried");
    result.set_message(poisonous + "; the last: " + result.message());
    FinishJob(batch, record, result);
    return;
  }
  Log("job " + job + " crashed worker " + name + " (" + result.message() + "); back to the front of the queue, crash " +
      std::to_string(record.crashes) + " of " + std::to_string(options_.max_crashes));
  Enqueue(batch_id, record, true);
  ++counters_.jobs_requeued;
}

void Broker::OnWorkerHeartbeat(const std::string& worker) {
  if (workers_.count(worker) != 0) return;  // its expiry moved on already
  // After a broker restart, a worker's socket reconnects by itself and keeps heartbeating: tell it to start over.
  v1::BrokerToWorker reply;
  reply.set_protocol_version(kProtocolVersion);
  reply.mutable_disconnect()->set_reason("unknown worker: connect again and send READY");
  SendToWorker(worker, reply);
}

void Broker::OnWorkerDisconnect(const std::string& worker, const v1::Disconnect& disconnect) {
  if (workers_.count(worker) == 0) return;
  // A worker that says goodbye did not die of its jobs: they go back to the queue without counting a loss.
  LoseWorker(worker, "left (" + disconnect.reason() + ")", false);
}

void Broker::OnClientMessage(const std::string& client, zmq::message_t& payload) {
  const proto::EnvelopeCheck check = proto::ParseEnvelope(payload.data(), payload.size(), client_in_);
  if (check != proto::EnvelopeCheck::kOk) {
    std::string why(proto::Describe(check));
    if (check == proto::EnvelopeCheck::kWrongVersion) {
      why +=
          " " + std::to_string(client_in_.protocol_version()) + " (expected " + std::to_string(kProtocolVersion) + ")";
    }
    DropMessage("client", client, why);
    return;
  }
  auto known = clients_.find(client);
  if (known != clients_.end()) known->second.expiry = now_ + liveness_period_;
  switch (client_in_.body_case()) {
    case v1::ClientToBroker::kSubmit: OnClientSubmit(client, *client_in_.mutable_submit()); break;
    case v1::ClientToBroker::kHeartbeat: OnClientHeartbeat(client); break;
    case v1::ClientToBroker::kCancel: OnClientCancel(client, client_in_.cancel()); break;
    case v1::ClientToBroker::kDisconnect: OnClientDisconnect(client, client_in_.disconnect()); break;
    case v1::ClientToBroker::BODY_NOT_SET: break;  // ParseEnvelope rejected it already
  }
}

namespace {

// What is wrong with a SUBMIT, or "" when nothing is.
std::string CheckSubmit(const v1::Submit& submit) {
  if (submit.batch_id().empty()) return "empty batch_id";
  if (submit.client_id().empty()) return "empty client_id";
  if (submit.batch_id().size() > kMaxIdBytes) return "batch_id longer than " + std::to_string(kMaxIdBytes) + " bytes";
  if (submit.client_id().size() > kMaxIdBytes) {
    return "client_id longer than " + std::to_string(kMaxIdBytes) + " bytes";
  }
  if (submit.owner_token().size() < kMinOwnerTokenBytes || submit.owner_token().size() > kMaxOwnerTokenBytes) {
    return "owner_token of " + std::to_string(submit.owner_token().size()) + " bytes (expected " +
           std::to_string(kMinOwnerTokenBytes) + "–" + std::to_string(kMaxOwnerTokenBytes) +
           " random bytes; a client library from before leases and owner tokens?)";
  }
  std::unordered_set<std::string_view> ids;
  for (int i = 0; i < submit.jobs_size(); ++i) {
    const v1::Job& job = submit.jobs(i);
    if (job.job_id().empty()) return "job " + std::to_string(i) + ": empty job_id";
    if (job.job_id().size() > kMaxJobIdBytes) {
      return "job " + std::to_string(i) + ": job_id longer than " + std::to_string(kMaxJobIdBytes) + " bytes";
    }
    const std::string where = "job " + std::to_string(i) + " (id '" + job.job_id() + "'): ";
    if (!ids.insert(job.job_id()).second) return where + "job_id repeated within the SUBMIT";
    if (!job.batch_id().empty() && job.batch_id() != submit.batch_id()) {
      return where + "batch_id '" + job.batch_id() + "' differs from the SUBMIT's '" + submit.batch_id() + "'";
    }
    if (job.protocol_version() != kProtocolVersion) {
      return where + "protocol_version " + std::to_string(job.protocol_version()) + " (expected " +
             std::to_string(kProtocolVersion) + ")";
    }
  }
  return "";
}

}  // namespace

void Broker::OnClientSubmit(const std::string& client, v1::Submit& submit) {
  const std::string& batch_id = submit.batch_id();
  std::string problem = CheckSubmit(submit);
  auto batch_entry = batches_.find(batch_id);
  auto client_entry = clients_.find(client);
  // A batch belongs to the holder of the token that opened it (and, with CURVE, to that client's key): a batch id
  // and a client id are names, printed in logs; the token is a secret, never sent back nor logged.
  if (problem.empty() && batch_entry != batches_.end() &&
      !SameSecret(batch_entry->second.owner_token, submit.owner_token())) {
    problem = "batch '" + batch_id + "' belongs to another client";
  }
  if (problem.empty() && batch_entry != batches_.end() && !batch_entry->second.client_key.empty() &&
      batch_entry->second.client_key != client_key_) {
    problem = "batch '" + batch_id + "' belongs to another client key";
  }
  if (problem.empty() && client_entry != clients_.end() && client_entry->second.client_id != submit.client_id()) {
    problem = "this connection submitted as client '" + client_entry->second.client_id + "' before";
  }
  if (!problem.empty()) {
    ++counters_.submits_rejected;
    Log("rejected a SUBMIT from client " + Hex(client) + ": " + problem);
    v1::BrokerToClient reply;
    reply.set_protocol_version(kProtocolVersion);
    reply.mutable_error()->set_batch_id(batch_id);
    reply.mutable_error()->set_message(problem);
    SendToClient(client, reply);
    return;
  }

  if (client_entry == clients_.end()) {
    client_entry = clients_.try_emplace(client).first;
    client_entry->second.client_id = submit.client_id();
    client_entry->second.expiry = now_ + liveness_period_;
  }
  if (batch_entry == batches_.end()) {
    batch_entry = batches_.try_emplace(batch_id).first;
    batch_entry->second.client = client;
    batch_entry->second.client_id = submit.client_id();
    batch_entry->second.client_key = client_key_;
    batch_entry->second.owner_token = submit.owner_token();
    if (journal_) journal_->AddBatch(batch_id, submit.client_id(), submit.owner_token(), client_key_);
    Log("client " + submit.client_id() + " opened batch " + batch_id);
  } else if (batch_entry->second.client != client) {
    // The same client on a new connection (it reconnected): results go to the new one from now on.
    auto previous = clients_.find(batch_entry->second.client);
    if (previous != clients_.end()) previous->second.batches.erase(batch_id);
    batch_entry->second.client = client;
    batch_entry->second.client_id = submit.client_id();
    Log("batch " + batch_id + " of client " + submit.client_id() + " moved to its new connection");
  }
  client_entry->second.batches.insert(batch_id);

  Batch& batch = batch_entry->second;
  const int job_count = submit.jobs_size();
  for (int i = 0; i < job_count; ++i) {
    v1::Job& job = *submit.mutable_jobs(i);
    auto [entry, inserted] = batch.jobs.try_emplace(job.job_id());
    if (inserted) NoteJobHeld();
    JobRecord& record = entry->second;
    // A job already pending stays as it is. A finished one submitted again (its client never saw the result, e.g.
    // it went to a connection that has since closed, or the broker restarted) gets its stored result when the
    // journal has one, and runs again otherwise.
    if (!inserted && record.state != JobState::kFinished) continue;
    if (journal_ && ResendStoredResult(client, batch_id, job.job_id())) {
      if (inserted) {  // finished records are not kept (FinishJob): the journal has it
        batch.jobs.erase(entry);
        --jobs_held_;
      }
      continue;
    }
    record.job = std::move(job);
    record.job.set_batch_id(batch_id);
    record.job.set_attempt(0);
    record.losses = 0;
    record.dispatches = 0;
    record.lost_by.clear();
    record.crashes = 0;
    record.crashed_by.clear();
    record.accepted_at = now_;
    Enqueue(batch_id, record, false);
    ++counters_.jobs_accepted;
  }
  v1::BrokerToClient reply;
  reply.set_protocol_version(kProtocolVersion);
  v1::Accepted& accepted = *reply.mutable_accepted();
  accepted.set_batch_id(batch_id);
  accepted.set_job_count(static_cast<std::uint32_t>(job_count));
  accepted.set_queued(queued_count_);
  SendToClient(client, reply);
}

void Broker::OnClientHeartbeat(const std::string& client) {
  if (clients_.count(client) != 0) return;  // its expiry moved on already
  // After a broker restart a client's socket reconnects by itself: tell it to start over and submit again.
  v1::BrokerToClient reply;
  reply.set_protocol_version(kProtocolVersion);
  reply.mutable_disconnect()->set_reason("unknown client: connect again and submit the outstanding jobs");
  SendToClient(client, reply);
}

void Broker::OnClientCancel(const std::string& client, const v1::Cancel& cancel) {
  auto batch = batches_.find(cancel.batch_id());
  if (batch == batches_.end() || batch->second.client != client) return;
  auto owner = clients_.find(client);
  if (owner != clients_.end()) owner->second.batches.erase(cancel.batch_id());
  Log("client " + batch->second.client_id + " cancelled batch " + cancel.batch_id());
  DropBatch(cancel.batch_id());
}

void Broker::OnClientDisconnect(const std::string& client, const v1::Disconnect& disconnect) {
  if (clients_.count(client) == 0) return;
  DropClient(client, "left (" + disconnect.reason() + ")", false);
}

// ---------------------------------------------------------------------------------------------------------------
// The clock

void Broker::OnTick(Clock::time_point now) {
  SendHeartbeats();
  PurgeLostWorkers(now);
  ExpireLeases(now);
  PurgeLostClients(now);
  PurgeUnclaimedBatches(now);
}

void Broker::SendHeartbeats() {
  std::vector<std::string> gone_workers;
  std::vector<std::string> gone_clients;
  v1::BrokerToWorker to_worker;
  to_worker.set_protocol_version(kProtocolVersion);
  to_worker.mutable_heartbeat();
  for (const auto& [worker, record] : workers_) {
    if (!SendToWorker(worker, to_worker)) gone_workers.push_back(worker);
  }
  v1::BrokerToClient to_client;
  to_client.set_protocol_version(kProtocolVersion);
  to_client.mutable_heartbeat();
  for (const auto& [client, record] : clients_) {
    if (!SendToClient(client, to_client)) gone_clients.push_back(client);
  }
  for (const std::string& worker : gone_workers) LoseWorker(worker, "connection closed", true);
  for (const std::string& client : gone_clients) DropClient(client, "connection closed", true);
}

void Broker::PurgeLostWorkers(Clock::time_point now) {
  std::vector<std::string> silent;
  for (const auto& [worker, record] : workers_) {
    if (record.expiry <= now) silent.push_back(worker);
  }
  for (const std::string& worker : silent) LoseWorker(worker, "silent for " + Seconds(liveness_period_), true);
}

void Broker::ExpireLeases(Clock::time_point now) {
  std::vector<std::pair<std::string, std::string>> overdue;  // worker, why
  for (const auto& [worker_id, worker] : workers_) {
    for (const JobKey& key : worker.holding) {
      const JobRecord* record = FindJob(key);
      if (record == nullptr || record->state != JobState::kDispatched || record->lease_deadline > now) continue;
      const double limit = record->job.time_limit_seconds();
      overdue.emplace_back(worker_id, "held job " + key.first + "/" + key.second + " past its lease (time limit " +
                                          (limit > 0 ? Seconds(std::chrono::duration_cast<Clock::duration>(
                                                           std::chrono::duration<double>(limit)))
                                                     : "none given") +
                                          ", leased for " + Seconds(LeaseLength(limit)) + ")");
      break;
    }
  }
  for (const auto& [worker_id, why] : overdue) {
    ++counters_.leases_expired;
    v1::BrokerToWorker reply;
    reply.set_protocol_version(kProtocolVersion);
    reply.mutable_disconnect()->set_reason(why + ": connect again and send READY");
    SendToWorker(worker_id, reply);
    LoseWorker(worker_id, why, true);
  }
}

Broker::Clock::duration Broker::LeaseLength(double time_limit_seconds) const {
  // Capped at 1e9 s (32 years) so that the lease fits a steady_clock duration.
  const double limit = std::isfinite(time_limit_seconds) && time_limit_seconds > 0 ? std::min(time_limit_seconds, 1e9)
                                                                                 : options_.default_time_limit_seconds;
  return std::chrono::duration_cast<Clock::duration>(
             std::chrono::duration<double>(kLeaseFactor * limit + kLeaseMarginSeconds)) +
         liveness_period_;
}

void Broker::PurgeLostClients(Clock::time_point now) {
  std::vector<std::string> silent;
  for (const auto& [client, record] : clients_) {
    if (record.expiry <= now) silent.push_back(client);
  }
  for (const std::string& client : silent) DropClient(client, "silent for " + Seconds(liveness_period_), true);
}

void Broker::PurgeUnclaimedBatches(Clock::time_point now) {
  std::vector<std::string> unclaimed;
  for (const auto& [batch_id, batch] : batches_) {
    if (batch.client.empty() && batch.claim_deadline <= now) unclaimed.push_back(batch_id);
  }
  for (const std::string& batch_id : unclaimed) {
    ++counters_.batches_unclaimed;
    Log("batch " + batch_id + " of client " + batches_.at(batch_id).client_id +
        " dropped: restored from the journal, but its client did not come back");
    DropBatch(batch_id);
  }
}

// ---------------------------------------------------------------------------------------------------------------
// The journal

// Reads the journal back after a restart. Unfinished jobs go to the queue — those that were in flight first: their
// workers are gone or will reconnect, and their late results are refused (no lease of this broker's). Finished
// jobs keep their stored results for the client, which resubmits every job it has no result for when it finds
// the broker restarted. A batch whose client is not back within two liveness periods is dropped.
void Broker::Restore() {
  now_ = Clock::now();
  journal_->Begin();
  for (JournalBatch& stored : journal_->Batches()) {
    Batch& batch = batches_[stored.batch_id];
    batch.client_id = std::move(stored.client_id);
    batch.owner_token = std::move(stored.owner_token);
    batch.client_key = std::move(stored.client_key);
    batch.claim_deadline = now_ + 2 * liveness_period_;
  }
  std::uint64_t in_flight = 0;
  journal_->ForEachJob([&](JournalJob&& stored) {
    auto batch = batches_.find(stored.batch_id);
    if (batch == batches_.end()) return;  // a job of a batch being dropped when the broker died
    const std::string job_id = stored.job.job_id();
    if (stored.finished) {  // the journal keeps the result for a resubmission; the broker keeps no record
      ++counters_.results_restored;
      return;
    }
    auto [entry, inserted] = batch->second.jobs.try_emplace(job_id);
    if (inserted) NoteJobHeld();
    JobRecord& record = entry->second;
    record.job = std::move(stored.job);
    record.job.set_batch_id(stored.batch_id);
    record.losses = stored.losses;
    record.dispatches = stored.dispatches;
    record.lost_by = std::move(stored.lost_by);
    record.accepted_at = now_;
    in_flight += stored.dispatched ? 1 : 0;
    Enqueue(stored.batch_id, record, false);
    ++counters_.jobs_restored;
  });
  journal_->Commit();
  Log("journal " + journal_->path() + ": restored " + std::to_string(batches_.size()) + " batches, " +
      std::to_string(counters_.jobs_restored) + " jobs queued again (" + std::to_string(in_flight) +
      " of them were in flight), " + std::to_string(counters_.results_restored) + " results kept for their clients");
}

bool Broker::ResendStoredResult(const std::string& client, const std::string& batch_id, const std::string& job_id) {
  std::optional<v1::Result> stored = journal_->Result(batch_id, job_id);
  if (!stored) return false;
  v1::BrokerToClient message;
  message.set_protocol_version(kProtocolVersion);
  message.mutable_result()->Swap(&*stored);
  if (SendToClient(client, message)) {
    ++counters_.results_delivered;
    ++counters_.results_resent;
  }
  return true;
}

// ---------------------------------------------------------------------------------------------------------------
// Moving jobs

void Broker::Dispatch() {
  v1::BrokerToWorker message;
  message.set_protocol_version(kProtocolVersion);
  std::vector<JobKey> deferred;  // crashed jobs waiting for a worker they have not crashed yet
  while (true) {
    while (!ready_workers_.empty()) {  // skip workers lost since they were listed
      auto worker = workers_.find(ready_workers_.front());
      if (worker != workers_.end() && worker->second.in_ready_list) break;
      ready_workers_.pop_front();
    }
    if (ready_workers_.empty()) break;
    JobKey key;
    if (!PopQueued(key)) break;
    Batch& batch = batches_.at(key.first);
    JobRecord& record = batch.jobs.at(key.second);
    const auto chosen = ReadyWorkerFor(record);
    if (chosen == ready_workers_.end()) {
      deferred.push_back(std::move(key));
      continue;
    }
    const std::string worker_id = std::move(*chosen);
    ready_workers_.erase(chosen);
    Worker& worker = workers_.at(worker_id);
    worker.in_ready_list = false;
    record.job.set_attempt(static_cast<std::uint32_t>(record.losses));
    record.lease = proto::SecureRandomToken();
    *message.mutable_job() = record.job;
    message.mutable_job()->set_lease(record.lease);
    if (!SendToWorker(worker_id, message)) {
      Enqueue(key.first, record, true);  // never reached the worker: no loss for the job
      LoseWorker(worker_id, "connection closed", true);
      continue;
    }
    SetState(record, JobState::kDispatched);
    record.worker = worker_id;
    ++record.dispatches;
    record.dispatched_at = now_;
    worker.busy_until = std::max(worker.busy_until, now_) + LeaseLength(record.job.time_limit_seconds());
    record.lease_deadline = worker.busy_until;
    if (journal_) journal_->SaveDispatched(key.first, key.second, record.dispatches);
    if (worker.holding.insert(std::move(key)).second) ++in_flight_count_;
    ++counters_.jobs_dispatched;
    MakeReady(worker_id, worker);  // to the back of the list: the least recently served worker goes first
  }
  // Back to the front of the queue, in their order.
  for (auto key = deferred.rbegin(); key != deferred.rend(); ++key) {
    Enqueue(key->first, batches_.at(key->first).jobs.at(key->second), true);
  }
}

// Where a job goes: the least recently served ready worker — but a job that crashed workers before goes to the
// first ready one it has not crashed yet, and waits (end()) while only workers it crashed are ready and another
// one is busy: "crashed three workers" should mean three, not one worker three times. When it has crashed every
// worker there is, any will do.
std::list<std::string>::iterator Broker::ReadyWorkerFor(const JobRecord& record) {
  if (record.crashed_by.empty()) return ready_workers_.begin();
  const std::string crashed = ", " + record.crashed_by + ", ";
  const auto spared = [&](const Worker& worker) {
    return crashed.find(", " + worker.name + ", ") == std::string::npos;
  };
  for (auto candidate = ready_workers_.begin(); candidate != ready_workers_.end(); ++candidate) {
    auto worker = workers_.find(*candidate);
    if (worker != workers_.end() && worker->second.in_ready_list && spared(worker->second)) return candidate;
  }
  for (const auto& [id, worker] : workers_) {
    if (spared(worker)) return ready_workers_.end();
  }
  return ready_workers_.begin();
}

bool Broker::PopQueued(JobKey& key) {
  while (!queue_.empty()) {
    QueueEntry entry = std::move(queue_.front());
    queue_.pop_front();
    auto batch = batches_.find(entry.batch_id);
    if (batch == batches_.end()) continue;  // its client left
    auto job = batch->second.jobs.find(entry.job_id);
    if (job == batch->second.jobs.end()) continue;
    const JobRecord& record = job->second;
    if (record.state != JobState::kQueued || record.ticket != entry.ticket) continue;  // stale entry
    key = {std::move(entry.batch_id), std::move(entry.job_id)};
    return true;
  }
  return false;
}

Broker::JobRecord* Broker::FindJob(const JobKey& key) {
  auto batch = batches_.find(key.first);
  if (batch == batches_.end()) return nullptr;
  auto job = batch->second.jobs.find(key.second);
  return job == batch->second.jobs.end() ? nullptr : &job->second;
}

void Broker::Enqueue(const std::string& batch_id, JobRecord& record, bool at_front) {
  SetState(record, JobState::kQueued);
  record.worker.clear();
  record.lease = 0;
  record.ticket = next_ticket_++;
  if (journal_) journal_->SaveQueued(batch_id, record.job, record.ticket, record.losses, record.lost_by);
  QueueEntry entry{batch_id, record.job.job_id(), record.ticket};
  if (at_front) {
    queue_.push_front(std::move(entry));
  } else {
    queue_.push_back(std::move(entry));
  }
}

void Broker::NoteJobHeld() {
  ++jobs_held_;
  counters_.jobs_held_peak = std::max(counters_.jobs_held_peak, jobs_held_);
}

void Broker::SetState(JobRecord& record, JobState state) {
  if (record.state == JobState::kQueued) --queued_count_;
  if (state == JobState::kQueued) ++queued_count_;
  record.state = state;
}

void Broker::MakeReady(const std::string& worker_id, Worker& worker) {
  if (worker.in_ready_list || worker.holding.size() >= worker.credit) return;
  ready_workers_.push_back(worker_id);
  worker.in_ready_list = true;
}

void Broker::LoseWorker(const std::string& worker_id, const std::string& reason, bool counts_as_loss) {
  auto entry = workers_.find(worker_id);
  if (entry == workers_.end()) return;
  const Worker worker = std::move(entry->second);
  workers_.erase(entry);
  in_flight_count_ -= worker.holding.size();
  if (counts_as_loss) ++counters_.workers_lost;
  int requeued = 0;
  int failed = 0;
  // Back to the front of the queue, keeping their order among themselves.
  for (auto key = worker.holding.rbegin(); key != worker.holding.rend(); ++key) {
    auto batch = batches_.find(key->first);
    if (batch == batches_.end()) continue;
    auto job = batch->second.jobs.find(key->second);
    if (job == batch->second.jobs.end()) continue;
    JobRecord& record = job->second;
    if (record.state != JobState::kDispatched || record.worker != worker_id) continue;
    if (counts_as_loss) {
      ++record.losses;
      record.lost_by += (record.lost_by.empty() ? "" : ", ") + worker.name;
    }
    if (record.losses >= options_.max_worker_losses) {
      FailJob(batch->second, record, v1::Result::WORKER_LOST,
              "lost " + std::to_string(record.losses) + " workers while running (" + record.lost_by +
                  "); the last one: " + reason);
      ++failed;
    } else {
      Enqueue(key->first, record, true);
      ++counters_.jobs_requeued;
      ++requeued;
    }
  }
  std::string line = "worker " + worker.name + (counts_as_loss ? " lost: " : " ") + reason;
  if (requeued > 0) line += "; " + std::to_string(requeued) + " jobs back to the queue";
  if (failed > 0) line += "; " + std::to_string(failed) + " jobs failed with WORKER_LOST";
  Log(line);
}

void Broker::DropClient(const std::string& client, const std::string& reason, bool lost) {
  auto entry = clients_.find(client);
  if (entry == clients_.end()) return;
  const Client record = std::move(entry->second);
  clients_.erase(entry);
  std::uint64_t pending = 0;
  for (const std::string& batch_id : record.batches) {
    auto batch = batches_.find(batch_id);
    if (batch == batches_.end() || batch->second.client != client) continue;
    for (const auto& [job_id, job] : batch->second.jobs) pending += job.state != JobState::kFinished ? 1 : 0;
    DropBatch(batch_id);
  }
  if (!lost) {
    Log("client " + record.client_id + " " + reason +
        (pending > 0 ? "; dropped its " + std::to_string(pending) + " pending jobs" : ""));
  } else if (pending > 0) {
    ++counters_.clients_lost;
    Log("client " + record.client_id + " lost (" + reason + "); dropped its " + std::to_string(pending) +
        " pending jobs");
  } else {
    // A client stops heartbeating once it has every result: forgetting it is routine.
    Log("client " + record.client_id + " forgotten (" + reason + ", nothing pending)");
  }
}

void Broker::DropBatch(const std::string& batch_id) {
  auto batch = batches_.find(batch_id);
  if (batch == batches_.end()) return;
  for (auto& [job_id, record] : batch->second.jobs) SetState(record, JobState::kFinished);
  jobs_held_ -= batch->second.jobs.size();
  batches_.erase(batch);
  if (journal_) journal_->DropBatch(batch_id);
  // The queue entries of the batch are now stale; compact the queue when they dominate it.
  if (queued_count_ == 0) {
    queue_.clear();
  } else if (queue_.size() > 2 * queued_count_ + 1024) {
    std::deque<QueueEntry> live;
    for (QueueEntry& entry : queue_) {
      auto owner = batches_.find(entry.batch_id);
      if (owner == batches_.end()) continue;
      auto job = owner->second.jobs.find(entry.job_id);
      if (job == owner->second.jobs.end() || job->second.state != JobState::kQueued ||
          job->second.ticket != entry.ticket) {
        continue;
      }
      live.push_back(std::move(entry));
    }
    queue_ = std::move(live);
  }
}

void Broker::FinishJob(Batch& batch, JobRecord& record, v1::Result& result) {
  result.set_protocol_version(kProtocolVersion);
  result.set_batch_id(record.job.batch_id());
  result.set_job_id(record.job.job_id());
  if (result.status() == v1::Result::STATUS_UNSPECIFIED) {
    result.set_status(v1::Result::INTERNAL_ERROR);
    if (result.message().empty()) result.set_message("the worker sent a result without a status");
  }
  result.set_attempts(static_cast<std::uint32_t>(record.dispatches));
  result.mutable_timings()->set_queued_seconds(
      SecondsBetween(record.accepted_at, record.dispatches > 0 ? record.dispatched_at : now_));
  SetState(record, JobState::kFinished);
  record.worker.clear();
  record.lease = 0;
  if (journal_) journal_->SaveFinished(record.job.batch_id(), record.job.job_id(), result);
  // The record goes: a finished job needs nothing from the broker's memory, so a batch streamed through a window
  // keeps the broker's memory in proportion to its pending jobs, not to every job it ever had. A late or forged
  // result for it is refused as one for an unknown job; a resubmission of it runs again, or, with a journal,
  // gets the stored result (OnClientSubmit).
  const std::string job_id = record.job.job_id();
  batch.jobs.erase(job_id);  // `record` dangles from here on
  --jobs_held_;

  v1::BrokerToClient message;
  message.set_protocol_version(kProtocolVersion);
  message.mutable_result()->Swap(&result);
  // A restored batch whose client is not back yet: the journal keeps the result until the client asks again.
  if (!batch.client.empty() && SendToClient(batch.client, message)) ++counters_.results_delivered;
}

void Broker::FailJob(Batch& batch, JobRecord& record, v1::Result::Status status, const std::string& message) {
  v1::Result result;
  result.set_status(status);
  result.set_message(message);
  auto last = record.lost_by.rfind(", ");
  result.set_worker_id(last == std::string::npos ? record.lost_by : record.lost_by.substr(last + 2));
  FinishJob(batch, record, result);
}

// ---------------------------------------------------------------------------------------------------------------
// Outgoing traffic

bool Broker::Send(zmq::socket_t& socket, const std::string& peer, const google::protobuf::Message& message) {
  out_.clear();
  message.SerializeToString(&out_);
  try {
    socket.send(zmq::buffer(peer), zmq::send_flags::sndmore);
    socket.send(zmq::buffer(out_), zmq::send_flags::none);
  } catch (const zmq::error_t& error) {
    if (error.num() == EHOSTUNREACH) return false;  // the peer's connection is gone
    throw;
  }
  return true;
}

bool Broker::SendToWorker(const std::string& worker, const v1::BrokerToWorker& message) {
  return Send(worker_socket_, worker, message);
}

bool Broker::SendToClient(const std::string& client, const v1::BrokerToClient& message) {
  return Send(client_socket_, client, message);
}

void Broker::SayGoodbye() {
  v1::BrokerToWorker to_worker;
  to_worker.set_protocol_version(kProtocolVersion);
  to_worker.mutable_disconnect()->set_reason("broker shutting down");
  for (const auto& [worker, record] : workers_) SendToWorker(worker, to_worker);
  v1::BrokerToClient to_client;
  to_client.set_protocol_version(kProtocolVersion);
  to_client.mutable_disconnect()->set_reason("broker shutting down");
  for (const auto& [client, record] : clients_) SendToClient(client, to_client);
  Log("stopped: told " + std::to_string(workers_.size()) + " workers and " + std::to_string(clients_.size()) +
      " clients");
}

// ---------------------------------------------------------------------------------------------------------------
// Bookkeeping

void Broker::DropMessage(std::string_view side, const std::string& peer, const std::string& why) {
  ++counters_.messages_dropped;
  if (warned_peers_.size() >= kMaxWarnedPeers) warned_peers_.clear();
  if (!warned_peers_.insert(std::string(side) + peer).second) return;
  std::string name = Hex(peer);
  if (side == "worker") name = WorkerName(peer);
  Log("dropped a message from " + std::string(side) + " " + name + ": " + why +
      " (further bad messages from this peer are dropped without a log line)");
}

std::string Broker::WorkerName(const std::string& worker) const {
  auto entry = workers_.find(worker);
  return entry == workers_.end() ? Hex(worker) : entry->second.name;
}

void Broker::Log(const std::string& line) const {
  const std::string text = EscapeForLog(line);
  if (options_.log) {
    options_.log(text);
  } else {
    std::cerr << "orcs-broker: " << text << std::endl;
  }
}

void Broker::PublishStats() {
  BrokerStats snapshot = counters_;
  snapshot.workers = static_cast<int>(workers_.size());
  snapshot.clients = static_cast<int>(clients_.size());
  snapshot.batches = static_cast<int>(batches_.size());
  snapshot.queued = queued_count_;
  snapshot.in_flight = in_flight_count_;
  snapshot.jobs_held = jobs_held_;
  if (zap_) snapshot.handshakes_refused = zap_->stats().refused;
  std::lock_guard lock(stats_mutex_);
  stats_ = snapshot;
}

}  // namespace orcs::broker
