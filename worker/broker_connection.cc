#include "worker/broker_connection.h"

#include <sys/eventfd.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <functional>
#include <iostream>
#include <stdexcept>
#include <utility>
#include <vector>

#include "base/log_sink.h"
#include "net/envelope_check.h"
#include "proto/envelope.h"

namespace orcs::worker {
namespace {

using Clock = std::chrono::steady_clock;
using proto::kProtocolVersion;

constexpr int kMaxCredit = 1024;

std::string HostName() {
  char host[256] = {};
  if (::gethostname(host, sizeof host - 1) != 0) std::snprintf(host, sizeof host, "worker");
  return host;
}

std::string DefaultWorkerId() { return HostName() + "-" + std::to_string(::getpid()); }

// READY: who the worker is, where it runs (for the broker's status), how many jobs it may hold and how often it
// heartbeats (the broker waits for the slower of the two).
v1::WorkerToBroker ReadyMessage(const std::string& worker_id, int credit, std::chrono::milliseconds heartbeat) {
  v1::WorkerToBroker ready;
  ready.set_protocol_version(kProtocolVersion);
  ready.mutable_ready()->set_worker_id(worker_id);
  ready.mutable_ready()->set_credit(static_cast<std::uint32_t>(credit));
  ready.mutable_ready()->set_host(HostName().substr(0, 128));
  ready.mutable_ready()->set_heartbeat_ms(static_cast<std::uint32_t>(heartbeat.count()));
  return ready;
}

WorkerConnectionOptions Checked(WorkerConnectionOptions options) {
  if (options.endpoint.empty()) throw std::invalid_argument("WorkerConnection: empty broker endpoint");
  if (options.credit < 1 || options.credit > kMaxCredit) {
    throw std::invalid_argument("WorkerConnection: credit " + std::to_string(options.credit) + " outside 1..1024");
  }
  if (options.heartbeat_interval.count() <= 0) {
    throw std::invalid_argument("WorkerConnection: heartbeat interval must be positive");
  }
  if (options.liveness < 2) throw std::invalid_argument("WorkerConnection: liveness must be at least 2");
  if (options.short_job_credit > kMaxCredit) {
    throw std::invalid_argument("WorkerConnection: short-job credit " + std::to_string(options.short_job_credit) +
                                " above 1024");
  }
  if (options.short_job.count() < 0) throw std::invalid_argument("WorkerConnection: negative short-job time");
  return options;
}

std::string Seconds(Clock::duration duration) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f s", std::chrono::duration<double>(duration).count());
  return text;
}

}  // namespace

WorkerConnection::WorkerConnection(WorkerConnectionOptions options)
    : options_(Checked(std::move(options))),
      worker_id_(options_.worker_id.empty() ? DefaultWorkerId() : options_.worker_id),
      dealer_(net::DealerOptionsFor<v1::WorkerToBroker>(options_, "worker", "WorkerConnection",
                                                         [this](const std::string& line) { Log(line); })),
      revoked_fd_(::eventfd(0, EFD_CLOEXEC | EFD_NONBLOCK)) {
  if (revoked_fd_ < 0) throw std::runtime_error(std::string("WorkerConnection: eventfd: ") + std::strerror(errno));
  wanted_credit_ = options_.credit;
  io_thread_ = std::jthread([this](std::stop_token stop) { IoLoop(stop); });
}

WorkerConnection::~WorkerConnection() {
  io_thread_.request_stop();  // its stop callback wakes the poll; it says goodbye and ends
  io_thread_.join();          // before the eventfd closes (the destructor's body runs before members go)
  ::close(revoked_fd_);
}

std::optional<v1::Job> WorkerConnection::NextJob(std::chrono::milliseconds timeout) {
  std::unique_lock lock(mutex_);
  job_arrived_.wait_for(lock, timeout, [this] { return !jobs_.empty() || !failure_.empty(); });
  if (jobs_.empty()) {
    if (!failure_.empty()) throw std::runtime_error(failure_);
    return std::nullopt;
  }
  v1::Job job = std::move(jobs_.front());
  jobs_.pop_front();
  ++in_hand_;
  leases_[{job.batch_id(), job.job_id()}] = job.lease();
  taken_at_ = Clock::now();
  return job;
}

void WorkerConnection::SendResult(v1::Result result) {
  result.set_protocol_version(kProtocolVersion);
  if (result.worker_id().empty()) result.set_worker_id(worker_id_);
  const Clock::time_point now = Clock::now();
  {
    std::lock_guard lock(mutex_);
    auto lease = leases_.find({result.batch_id(), result.job_id()});
    if (lease != leases_.end()) {
      result.set_lease(lease->second);
      leases_.erase(lease);
    }
    if (revoked_in_hand_.erase(result.lease()) > 0) {  // nobody waits for it: its credit is free already
      if (revoked_in_hand_.empty()) {
        std::uint64_t count = 0;
        [[maybe_unused]] const ssize_t drained = ::read(revoked_fd_, &count, sizeof count);
      }
      if (in_hand_ > 0) --in_hand_;
      return;
    }
    outbox_.push_back(std::move(result));
    if (in_hand_ == 1 && options_.short_job_credit > options_.credit) {  // one job in hand: its time is exact
      if (now - taken_at_ < options_.short_job) {
        if (++short_in_a_row_ >= kShortJobsToRaise) wanted_credit_ = options_.short_job_credit;
      } else {
        short_in_a_row_ = 0;
        wanted_credit_ = options_.credit;
      }
    }
    if (in_hand_ > 0) --in_hand_;
  }
  dealer_.Wake();
}

bool WorkerConnection::Revoked(const v1::Job& job) const {
  std::lock_guard lock(mutex_);
  return revoked_in_hand_.count(job.lease()) > 0;
}

WorkerConnectionStats WorkerConnection::stats() const {
  std::lock_guard lock(mutex_);
  return stats_;
}

void WorkerConnection::Log(const std::string& line) const {
  WriteLogLine(options_.log, "orcs-worker", line);
}

// ---------------------------------------------------------------------------------------------------------------
// The I/O thread

void WorkerConnection::IoLoop(std::stop_token stop) {
  stop_ = stop;
  const std::stop_callback wake_on_stop(stop, [this] { dealer_.Wake(); });
  try {
    Serve();
  } catch (const std::exception& error) {
    const std::string failure = "the connection to the broker at " + options_.endpoint + " failed: " + error.what();
    Log(failure);
    std::unique_lock lock(mutex_);
    failure_ = failure;
    job_arrived_.notify_all();
  }
}

void WorkerConnection::Serve() {
  Connect();
  dealer_.ScheduleHeartbeat(Clock::now());
  while (ServeOnce()) {
  }
  v1::WorkerToBroker goodbye;
  goodbye.set_protocol_version(kProtocolVersion);
  goodbye.mutable_disconnect()->set_reason("worker shutting down");
  dealer_.SendGoodbye(goodbye.SerializeAsString());
}

// Wait for the next heartbeat, the broker's deadline, a message or a result; then deal with each.
bool WorkerConnection::ServeOnce() {
  const Clock::time_point wake_at = std::min(dealer_.next_heartbeat(), dealer_.liveness_deadline());
  const net::DealerConnection::PollEvents events = dealer_.Poll(wake_at);
  if (events.handshakes_refused > 0) {
    std::lock_guard lock(mutex_);
    stats_.handshake_failures += events.handshakes_refused;
  }
  std::deque<v1::Result> sending;
  if (!SendOutbox(sending)) return false;
  if (events.readable) ReadBrokerMessages();
  HeartbeatAndWatchBroker();
  return true;
}

bool WorkerConnection::SendOutbox(std::deque<v1::Result>& sending) {
  bool stopping = false;
  int wanted_credit = 0;
  {
    std::lock_guard lock(mutex_);
    sending.swap(outbox_);
    stopping = stop_.stop_requested();
    wanted_credit = wanted_credit_;
  }
  for (v1::Result& result : sending) {
    v1::WorkerToBroker message;
    message.set_protocol_version(kProtocolVersion);
    *message.mutable_result() = std::move(result);
    dealer_.SendMessage(message);
  }
  // After the results, so that the broker frees their credit before it sees a lower one.
  if (!stopping && wanted_credit != announced_credit_) AnnounceCredit(wanted_credit);
  if (!sending.empty()) {
    std::lock_guard lock(mutex_);
    stats_.results_sent += sending.size();
  }
  return !stopping;
}

void WorkerConnection::ReadBrokerMessages() {
  dealer_.ReceiveAll(
      [this](const zmq::message_t& payload) { return OnBrokerMessage(payload) != Heard::kReconnected; },
      [this](const std::string& why) { DropMessage(why); });
}

void WorkerConnection::HeartbeatAndWatchBroker() {
  const Clock::time_point now = Clock::now();
  if (dealer_.HeartbeatIfDue(now)) {
    // A raised credit falls back once a whole heartbeat interval brought no job: the short batch is over, and
    // the next batch may hold long jobs, which must not pile up at one worker.
    bool idle = false;
    {
      std::lock_guard lock(mutex_);
      idle = stats_.jobs_received == jobs_at_last_heartbeat_ && announced_credit_ != options_.credit;
      jobs_at_last_heartbeat_ = stats_.jobs_received;
      if (idle) {
        short_in_a_row_ = 0;
        wanted_credit_ = options_.credit;
      }
    }
    if (idle) AnnounceCredit(options_.credit);
  }
  if (now >= dealer_.liveness_deadline()) {
    Reconnect("no answer from the broker at " + options_.endpoint + " for " + Seconds(dealer_.liveness_period()));
  }
}

void WorkerConnection::Connect() {
  dealer_.Open();
  announced_credit_ = options_.credit;  // a new connection starts from the base credit
  {
    std::lock_guard lock(mutex_);
    ++stats_.connections;  // before READY leaves, so that whoever sees the READY sees the count
    stats_.broker_answering = false;
    stats_.credit = static_cast<std::uint32_t>(options_.credit);
    short_in_a_row_ = 0;
    wanted_credit_ = options_.credit;
  }
  dealer_.SendMessage(ReadyMessage(worker_id_, options_.credit, options_.heartbeat_interval));
}

void WorkerConnection::AnnounceCredit(int credit) {
  dealer_.SendMessage(ReadyMessage(worker_id_, credit, options_.heartbeat_interval));
  announced_credit_ = credit;
  std::lock_guard lock(mutex_);
  stats_.credit = static_cast<std::uint32_t>(credit);
  ++stats_.credit_changes;
}

void WorkerConnection::Reconnect(const std::string& why) {
  std::size_t discarded = 0;
  {
    std::lock_guard lock(mutex_);
    discarded = jobs_.size();
    stats_.jobs_discarded += discarded;
    jobs_.clear();
  }
  std::string line = why + "; connecting again";
  if (discarded > 0) line += " (dropped " + std::to_string(discarded) + " jobs not started: the broker requeues them)";
  dealer_.ReportSilence(line);
  dealer_.Close();
  Connect();
}

WorkerConnection::Heard WorkerConnection::OnBrokerMessage(const zmq::message_t& payload) {
  const std::string rejection = net::CheckEnvelope(payload, in_);
  if (!rejection.empty()) {
    DropMessage(rejection);
    return Heard::kNothing;
  }
  {
    std::lock_guard lock(mutex_);
    stats_.broker_answering = true;
  }
  dealer_.MarkHeard();
  switch (in_.body_case()) {
    case v1::BrokerToWorker::kJob: {
      v1::Job& job = *in_.mutable_job();
      if (job.protocol_version() != kProtocolVersion) {
        AnswerWrongVersionJob(job);
        return Heard::kAlive;
      }
      {
        std::lock_guard lock(mutex_);
        jobs_.push_back(std::move(job));
        ++stats_.jobs_received;
      }
      job_arrived_.notify_one();
      return Heard::kAlive;
    }
    case v1::BrokerToWorker::kDisconnect:
      Reconnect("the broker at " + options_.endpoint + " said goodbye (" + in_.disconnect().reason() + ")");
      return Heard::kReconnected;
    case v1::BrokerToWorker::kHeartbeat:
      dealer_.NotePeerInterval(std::chrono::milliseconds(in_.heartbeat().interval_ms()));
      break;
    case v1::BrokerToWorker::kRevoke: OnRevoke(in_.revoke()); break;
    case v1::BrokerToWorker::BODY_NOT_SET: break;
  }
  return Heard::kAlive;
}

// Jobs not started yet are dropped here; a running one is marked, and the caller polling revoked_fd() stops it.
void WorkerConnection::OnRevoke(const v1::Revoke& revoke) {
  const std::set<std::uint64_t> leases(revoke.leases().begin(), revoke.leases().end());
  std::size_t unstarted = 0;
  std::size_t running = 0;
  {
    std::lock_guard lock(mutex_);
    unstarted = std::erase_if(jobs_, [&](const v1::Job& job) { return leases.count(job.lease()) > 0; });
    for (const auto& [key, lease] : leases_) {
      if (leases.count(lease) > 0 && revoked_in_hand_.insert(lease).second) ++running;
    }
    stats_.jobs_revoked += unstarted + running;
  }
  if (running > 0) {
    const std::uint64_t one = 1;
    [[maybe_unused]] const ssize_t written = ::write(revoked_fd_, &one, sizeof one);
  }
  if (unstarted + running == 0) return;  // answered already
  Log("the broker revoked " + std::to_string(unstarted + running) + " jobs (" + revoke.reason() + "): " +
      std::to_string(running) + " running stopped, " + std::to_string(unstarted) + " not started dropped");
}

// Answers a job of another protocol version, so that the broker gets its credit back and the client learns why.
void WorkerConnection::AnswerWrongVersionJob(const v1::Job& job) {
  v1::WorkerToBroker answer;
  answer.set_protocol_version(kProtocolVersion);
  v1::Result& result = *answer.mutable_result();
  result.set_protocol_version(kProtocolVersion);
  result.set_job_id(job.job_id());
  result.set_batch_id(job.batch_id());
  result.set_worker_id(worker_id_);
  result.set_status(v1::Result::INVALID_INPUT);
  result.set_message("job protocol version " + std::to_string(job.protocol_version()) + "; this worker speaks " +
                     std::to_string(kProtocolVersion));
  dealer_.SendMessage(answer);
}

void WorkerConnection::DropMessage(const std::string& why) {
  {
    std::lock_guard lock(mutex_);
    ++stats_.messages_dropped;
  }
  dealer_.ReportDropped(why);
}

}  // namespace orcs::worker
