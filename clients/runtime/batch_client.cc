#include "clients/runtime/batch_client.h"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdio>
#include <functional>
#include <iostream>
#include <utility>

#include "base/log_sink.h"
#include "net/envelope_check.h"
#include "proto/envelope.h"
#include "proto/secure_random.h"

namespace orcs::runtime {
namespace {

using proto::kProtocolVersion;

// "<hostname>-<pid>-<n>": unique among the processes alive at the same time, without clocks or randomness.
std::string NewClientId() {
  static std::atomic<unsigned> counter{0};
  char host[256] = {};
  if (::gethostname(host, sizeof host - 1) != 0) std::snprintf(host, sizeof host, "client");
  return std::string(host) + "-" + std::to_string(::getpid()) + "-" + std::to_string(++counter);
}

BatchClientOptions Checked(BatchClientOptions options) {
  if (options.endpoint.empty()) throw std::invalid_argument("BatchClient: empty broker endpoint");
  if (options.heartbeat_interval.count() <= 0)
    throw std::invalid_argument("BatchClient: heartbeat interval must be positive");
  if (options.liveness < 2) throw std::invalid_argument("BatchClient: liveness must be at least 2");
  if (options.connect_timeout.count() <= 0)
    throw std::invalid_argument("BatchClient: connect timeout must be positive");
  if (options.reconnect_timeout.count() <= 0) {
    throw std::invalid_argument("BatchClient: reconnect timeout must be positive");
  }
  if (options.max_submit_bytes == 0) throw std::invalid_argument("BatchClient: max_submit_bytes must be positive");
  return options;
}

// "3 s", "0.5 s".
std::string Seconds(std::chrono::steady_clock::duration duration) {
  char text[32];
  std::snprintf(text, sizeof text, "%g s", std::chrono::duration<double>(duration).count());
  return text;
}

}  // namespace

BatchClient::BatchClient(BatchClientOptions options)
    : options_(Checked(std::move(options))),
      client_id_(NewClientId()),
      batch_id_(options_.batch_id.empty() ? proto::SecureRandomHex(16) : options_.batch_id),
      owner_token_(proto::SecureRandomBytes(16)),
      dealer_(net::DealerOptionsFor<v1::ClientToBroker>(options_, "client", "BatchClient",
                                                         [this](const std::string& line) { Log(line); })) {
  io_thread_ = std::thread([this] { IoLoop(); });
}

BatchClient::~BatchClient() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  changed_.notify_all();  // the I/O thread waits on it after a failure
  dealer_.Wake();
  io_thread_.join();
}

void BatchClient::Submit(std::vector<v1::Job> jobs) {
  std::unordered_set<std::string_view> ids;
  for (std::size_t i = 0; i < jobs.size(); ++i) {
    const std::string& id = jobs[i].job_id();
    if (id.empty()) throw std::invalid_argument("job " + std::to_string(i) + ": empty job_id");
    if (!ids.insert(id).second)
      throw std::invalid_argument("job " + std::to_string(i) + ": job_id '" + id + "' repeated");
  }
  for (v1::Job& job : jobs) {
    job.set_batch_id(batch_id_);
    job.set_protocol_version(kProtocolVersion);
  }
  std::unique_lock lock(mutex_);
  if (!error_.empty()) throw BatchClientError(error_);
  for (const v1::Job& job : jobs) {
    if (outstanding_ids_.count(job.job_id()) != 0) {
      throw std::invalid_argument("job_id '" + job.job_id() + "' was submitted to batch " + batch_id_ +
                                  " before and has no result yet");
    }
  }
  // Only the outstanding ids are kept: a set of every id ever submitted would grow with the batch.
  for (const v1::Job& job : jobs) outstanding_ids_.insert(job.job_id());
  stats_.max_outstanding = std::max<std::uint64_t>(stats_.max_outstanding, outstanding_ids_.size());
  const std::uint64_t submission = ++submissions_;
  to_submit_.push_back(std::move(jobs));
  lock.unlock();
  dealer_.Wake();
  lock.lock();
  // The I/O thread answers within connect_timeout or reconnect_timeout (plus the liveness period that reveals a
  // lost broker); the bound here only guards against a bug there.
  const auto bound = options_.connect_timeout + options_.reconnect_timeout +
                     options_.heartbeat_interval * (options_.liveness + 2) + std::chrono::seconds(5);
  if (!changed_.wait_for(lock, bound, [&] { return accepted_through_ >= submission || !error_.empty(); })) {
    error_ = "no answer from the client's I/O thread after " + Seconds(bound);
  }
  if (!error_.empty()) throw BatchClientError(error_);
}

std::optional<v1::Result> BatchClient::Next(std::chrono::milliseconds timeout) {
  std::unique_lock lock(mutex_);
  changed_.wait_for(lock, timeout,
                    [this] { return !results_.empty() || !error_.empty() || outstanding_ids_.empty(); });
  if (!results_.empty()) {
    v1::Result result = std::move(results_.front());
    results_.pop_front();
    outstanding_ids_.erase(result.job_id());
    return result;
  }
  if (!error_.empty()) throw BatchClientError(error_);
  return std::nullopt;
}

std::size_t BatchClient::outstanding() const {
  std::lock_guard lock(mutex_);
  return outstanding_ids_.size();
}

BatchClientStats BatchClient::stats() const {
  std::lock_guard lock(mutex_);
  return stats_;
}

void BatchClient::Log(const std::string& line) const {
  WriteLogLine(options_.log, "orcs-batch", line);
}

void BatchClient::Fail(const std::string& message) {
  {
    std::lock_guard lock(mutex_);
    if (error_.empty()) error_ = message;
  }
  changed_.notify_all();
  // Nothing is outstanding any more: the client goes idle and stops heartbeating.
  outstanding_.clear();
  order_.clear();
  unanswered_.clear();
}

// ---------------------------------------------------------------------------------------------------------------
// The I/O thread

void BatchClient::IoLoop() {
  try {
    Serve();
  } catch (const std::exception& error) {
    Fail(std::string("the client's connection to ") + options_.endpoint + " failed: " + error.what());
    // Stay until the destructor asks, so that it finds a thread to join.
    std::unique_lock lock(mutex_);
    changed_.wait(lock, [this] { return stopping_; });
  }
  dealer_.Close();
}

bool BatchClient::Active() const {
  return dealer_.is_open() && (!outstanding_.empty() || !unanswered_.empty());
}

// One turn: wait, take the callers' submissions, read the broker, then heartbeat and watch the broker's liveness.
void BatchClient::Serve() {
  std::deque<std::vector<v1::Job>> taken;
  while (true) {
    const std::optional<Clock::time_point> wake_at = WakeAt();
    const net::DealerConnection::PollEvents events = dealer_.Poll(wake_at);
    ExcuseOversleep(wake_at);
    bool stopping = false;
    bool failed = false;
    {
      std::lock_guard lock(mutex_);
      stats_.handshake_failures += events.handshakes_refused;
      taken.swap(to_submit_);
      stopping = stopping_;
      failed = !error_.empty();
    }
    if (stopping) {
      SayGoodbye();
      return;
    }
    SubmitTaken(taken, failed);
    taken.clear();
    if (events.readable) ReadBrokerMessages();
    if (Active()) CheckBroker(Clock::now());
  }
}

// A poll that returned far later than it was due means this process was stopped (SIGSTOP, ^Z): the broker had no
// chance to be heard meanwhile, so its silence is excused and it is asked again before anything is judged.
void BatchClient::ExcuseOversleep(std::optional<Clock::time_point> wake_at) {
  if (!wake_at || !Active()) return;
  const Clock::duration late = Clock::now() - *wake_at;
  if (late > options_.heartbeat_interval * 2) {
    dealer_.ExcuseAbsence(late);
    if (!heard_) active_since_ += late;
  }
}

// An idle client sleeps until a caller wakes it; an active one until its next heartbeat or deadline.
std::optional<BatchClient::Clock::time_point> BatchClient::WakeAt() const {
  if (!Active()) return std::nullopt;
  const Clock::time_point deadline =
      !heard_ ? active_since_ + options_.connect_timeout : dealer_.liveness_deadline();
  return std::min(dealer_.next_heartbeat(), deadline);
}

void BatchClient::SubmitTaken(std::deque<std::vector<v1::Job>>& taken, bool failed) {
  for (std::vector<v1::Job>& jobs : taken) {
    const std::uint64_t submission = ++latest_sent_;
    if (failed) continue;
    if (!dealer_.is_open()) Connect();
    const Clock::time_point now = Clock::now();
    if (!Active()) {  // from idle: a fresh start for the timeouts
      heard_ = false;
      active_since_ = now;
      dealer_.ScheduleHeartbeat(now);
    }
    std::vector<const v1::Job*> sending;
    sending.reserve(jobs.size());
    for (v1::Job& job : jobs) {
      order_.push_back(job.job_id());
      const std::string id = job.job_id();
      sending.push_back(&(outstanding_[id] = std::move(job)));
    }
    SendJobs(sending, submission);
    // The broker cannot answer before the last SUBMIT has left: a large submission may keep this thread busy
    // serialising for longer than connect_timeout, which is no sign of a missing broker. Count from here.
    if (!heard_) active_since_ = Clock::now();
  }
}

void BatchClient::ReadBrokerMessages() {
  dealer_.ReceiveAll([this](const zmq::message_t& payload) { return OnBrokerMessage(payload); },  // false: socket gone
                     [this](const std::string& why) { DropMessage(why); });
}

// A broker that never answered fails the client after connect_timeout; one that falls silent is connected to
// again after the liveness period, and given up after reconnect_timeout.
void BatchClient::CheckBroker(Clock::time_point now) {
  dealer_.HeartbeatIfDue(now);
  if (!heard_) {
    if (now - active_since_ >= options_.connect_timeout) {
      const std::string& handshake = dealer_.last_handshake_failure();
      Fail("no broker answering at " + options_.endpoint + " after " + Seconds(options_.connect_timeout) +
           (handshake.empty() ? "" : " (the CURVE handshake failed: " + handshake + ")"));
    }
  } else if (now - dealer_.last_heard() >= options_.reconnect_timeout) {
    Fail("lost the broker at " + options_.endpoint + ": no answer for " + Seconds(now - dealer_.last_heard()) + " (" +
         std::to_string(outstanding_.size()) + " jobs without a result)");
  } else if (now >= dealer_.liveness_deadline()) {
    Reconnect("no answer from the broker at " + options_.endpoint + " for " + Seconds(now - dealer_.last_heard()));
  }
}

void BatchClient::SayGoodbye() {
  if (!dealer_.is_open()) return;
  v1::ClientToBroker goodbye;
  goodbye.set_protocol_version(kProtocolVersion);
  goodbye.mutable_disconnect()->set_reason("client done");
  dealer_.SendGoodbye(goodbye.SerializeAsString());
}

void BatchClient::Connect() {
  dealer_.Open();
  unanswered_.clear();
  std::lock_guard lock(mutex_);
  ++stats_.connections;
}

void BatchClient::Reconnect(const std::string& why) {
  dealer_.ReportSilence(why + "; connecting again (" + std::to_string(outstanding_.size()) + " jobs to submit again)");
  dealer_.Close();
  Connect();
  Resubmit();
}

void BatchClient::Resubmit() {
  std::deque<std::string> still;
  std::vector<const v1::Job*> sending;
  for (std::string& id : order_) {
    auto job = outstanding_.find(id);
    if (job == outstanding_.end()) continue;
    sending.push_back(&job->second);
    still.push_back(std::move(id));
  }
  order_ = std::move(still);
  std::uint64_t accepted_through = 0;
  {
    std::lock_guard lock(mutex_);
    accepted_through = accepted_through_;
  }
  // Every submission not yet accepted has its jobs among the outstanding ones: the resubmission answers them all.
  if (!sending.empty() || accepted_through < latest_sent_) SendJobs(sending, latest_sent_);
}

void BatchClient::SendJobs(const std::vector<const v1::Job*>& jobs, std::uint64_t submission) {
  std::size_t next = 0;
  do {
    v1::ClientToBroker message;
    message.set_protocol_version(kProtocolVersion);
    v1::Submit& submit = *message.mutable_submit();
    submit.set_batch_id(batch_id_);
    submit.set_client_id(client_id_);
    submit.set_owner_token(owner_token_);
    submit.set_batch_size(options_.batch_size);
    submit.set_heartbeat_ms(static_cast<std::uint32_t>(options_.heartbeat_interval.count()));
    std::size_t bytes = 0;
    while (next < jobs.size()) {
      const std::size_t size = jobs[next]->ByteSizeLong();
      if (submit.jobs_size() > 0 && bytes + size > options_.max_submit_bytes) break;
      *submit.add_jobs() = *jobs[next];
      bytes += size;
      ++next;
    }
    dealer_.SendMessage(message);
    unanswered_.push_back(submission);
    std::lock_guard lock(mutex_);
    ++stats_.submit_messages;
  } while (next < jobs.size());
}

bool BatchClient::OnBrokerMessage(const zmq::message_t& payload) {
  const std::string rejection = net::CheckEnvelope(payload, in_);
  if (!rejection.empty()) {
    DropMessage(rejection);
    return true;
  }
  heard_ = true;
  dealer_.MarkHeard();
  switch (in_.body_case()) {
    case v1::BrokerToClient::kAccepted: OnAccepted(); break;
    case v1::BrokerToClient::kResult: OnResult(*in_.mutable_result()); break;
    case v1::BrokerToClient::kError:
      Fail("the broker at " + options_.endpoint + " rejected batch " + batch_id_ + ": " + in_.error().message());
      break;
    case v1::BrokerToClient::kDisconnect:
      if (!Active()) {  // nothing to lose: connect again on the next Submit()
        dealer_.Close();
        return false;
      }
      Reconnect("the broker at " + options_.endpoint + " said goodbye (" + in_.disconnect().reason() + ")");
      return false;
    case v1::BrokerToClient::kHeartbeat:
      dealer_.NotePeerInterval(std::chrono::milliseconds(in_.heartbeat().interval_ms()));
      break;
    case v1::BrokerToClient::kStatus:  // a batch client never asks (StatusClient does, on its own connection)
    case v1::BrokerToClient::BODY_NOT_SET: break;
  }
  return true;
}

void BatchClient::OnAccepted() {
  if (unanswered_.empty()) return;  // an answer to a SUBMIT of a previous socket
  unanswered_.pop_front();
  const std::uint64_t through = unanswered_.empty() ? latest_sent_ : unanswered_.front() - 1;
  {
    std::lock_guard lock(mutex_);
    accepted_through_ = std::max(accepted_through_, through);
  }
  changed_.notify_all();
}

void BatchClient::OnResult(v1::Result& result) {
  auto job = result.batch_id() == batch_id_ ? outstanding_.find(result.job_id()) : outstanding_.end();
  if (job == outstanding_.end()) {  // answered already (a resubmission ran it twice) or not ours
    std::lock_guard lock(mutex_);
    ++stats_.duplicates_dropped;
    return;
  }
  outstanding_.erase(job);
  if (outstanding_.empty()) {
    order_.clear();
  } else {
    // Answered ids leave order_ lazily; drop them from the front at once, and compact the whole deque when a slow
    // job at the front keeps them from leaving, so that order_ stays in proportion to the outstanding jobs (a
    // batch streamed through a window would otherwise grow it by every id of the batch).
    while (!order_.empty() && outstanding_.count(order_.front()) == 0) order_.pop_front();
    if (order_.size() > 2 * outstanding_.size() + 1024) {
      std::erase_if(order_, [this](const std::string& id) { return outstanding_.count(id) == 0; });
    }
  }
  {
    std::lock_guard lock(mutex_);
    results_.push_back(std::move(result));
    ++stats_.results;
  }
  changed_.notify_all();
}

void BatchClient::DropMessage(const std::string& why) {
  {
    std::lock_guard lock(mutex_);
    ++stats_.messages_dropped;
  }
  dealer_.ReportDropped(why);
}

}  // namespace orcs::runtime
