#include "worker/broker_connection.h"

#include <sys/eventfd.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <iostream>
#include <stdexcept>
#include <utility>
#include <vector>

#include "proto/envelope.h"

namespace orcs::worker {
namespace {

using Clock = std::chrono::steady_clock;
using proto::kProtocolVersion;

constexpr int kMaxCredit = 1024;
constexpr int kGoodbyeLingerMs = 200;  // how long a DISCONNECT may take to leave at destruction

std::string DefaultWorkerId() {
  char host[256] = {};
  if (::gethostname(host, sizeof host - 1) != 0) std::snprintf(host, sizeof host, "worker");
  return std::string(host) + "-" + std::to_string(::getpid());
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
      context_(1) {
  if (!options_.curve_keys.empty()) curve_ = net::LoadCurvePeerKeys(options_.curve_keys, "worker");
  try {  // a malformed endpoint fails here, at once, rather than in the I/O thread
    zmq::socket_t probe(context_, zmq::socket_type::dealer);
    probe.set(zmq::sockopt::linger, 0);
    probe.connect(options_.endpoint);
  } catch (const zmq::error_t& error) {
    throw std::invalid_argument("WorkerConnection: cannot connect to '" + options_.endpoint + "': " + error.what());
  }
  wake_fd_ = ::eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
  if (wake_fd_ < 0) throw std::runtime_error("WorkerConnection: eventfd failed");
  wanted_credit_ = options_.credit;
  io_thread_ = std::thread([this] { IoLoop(); });
}

WorkerConnection::~WorkerConnection() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  job_arrived_.notify_all();
  Wake();
  io_thread_.join();
  ::close(wake_fd_);
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
  Wake();
}

WorkerConnectionStats WorkerConnection::stats() const {
  std::lock_guard lock(mutex_);
  return stats_;
}

void WorkerConnection::Wake() {
  const std::uint64_t one = 1;
  [[maybe_unused]] const ssize_t written = ::write(wake_fd_, &one, sizeof one);
}

void WorkerConnection::Log(const std::string& line) const {
  if (options_.log) {
    options_.log(line);
  } else {
    std::cerr << "orcs-worker: " << line << std::endl;
  }
}

// ---------------------------------------------------------------------------------------------------------------
// The I/O thread

void WorkerConnection::IoLoop() {
  try {
    Serve();
  } catch (const std::exception& error) {
    const std::string failure = "the connection to the broker at " + options_.endpoint + " failed: " + error.what();
    Log(failure);
    std::unique_lock lock(mutex_);
    failure_ = failure;
    job_arrived_.notify_all();
    job_arrived_.wait(lock, [this] { return stopping_; });  // stay until the destructor joins
  }
}

void WorkerConnection::Serve() {
  const Clock::duration liveness_period = options_.heartbeat_interval * options_.liveness;
  Connect();
  Clock::time_point next_heartbeat = Clock::now() + options_.heartbeat_interval;
  Clock::time_point broker_deadline = Clock::now() + liveness_period;
  std::deque<v1::Result> sending;
  std::uint64_t jobs_at_last_heartbeat = 0;
  v1::WorkerToBroker message;
  message.set_protocol_version(kProtocolVersion);
  while (true) {
    const Clock::time_point wake_at = std::min(next_heartbeat, broker_deadline);
    const auto wait = std::chrono::ceil<std::chrono::milliseconds>(std::max(wake_at - Clock::now(), Clock::duration{}));
    zmq::pollitem_t items[] = {{socket_->handle(), 0, ZMQ_POLLIN, 0},
                               {nullptr, wake_fd_, ZMQ_POLLIN, 0},
                               {monitor_ ? monitor_->socket().handle() : nullptr, 0, ZMQ_POLLIN, 0}};
    try {
      zmq::poll(items, monitor_ ? 3 : 2, wait);
    } catch (const zmq::error_t& error) {
      if (error.num() != EINTR) throw;
      continue;
    }
    if (items[1].revents & ZMQ_POLLIN) {
      std::uint64_t count = 0;
      [[maybe_unused]] const ssize_t read = ::read(wake_fd_, &count, sizeof count);
    }
    if (monitor_ && (items[2].revents & ZMQ_POLLIN)) ReadHandshakeFailures();

    bool stopping = false;
    int wanted_credit = 0;
    {
      std::lock_guard lock(mutex_);
      sending.swap(outbox_);
      stopping = stopping_;
      wanted_credit = wanted_credit_;
    }
    for (v1::Result& result : sending) {
      message.set_allocated_result(new v1::Result(std::move(result)));
      Send(message);
    }
    // After the results, so that the broker frees their credit before it sees a lower one.
    if (!stopping && wanted_credit != announced_credit_) AnnounceCredit(wanted_credit);
    if (!sending.empty()) {
      std::lock_guard lock(mutex_);
      stats_.results_sent += sending.size();
    }
    sending.clear();
    if (stopping) break;

    if (items[0].revents & ZMQ_POLLIN) {
      zmq::message_t payload;
      while (socket_->recv(payload, zmq::recv_flags::dontwait)) {
        if (payload.more()) {  // the protocol has one frame per message: drop the whole multipart message
          while (payload.more() && socket_->recv(payload, zmq::recv_flags::dontwait)) {
          }
          DropMessage("a message of several frames");
          continue;
        }
        const Heard heard = OnBrokerMessage(payload);
        if (heard == Heard::kNothing) continue;
        broker_deadline = Clock::now() + liveness_period;
        if (heard == Heard::kReconnected) break;  // that socket is gone
      }
    }

    const Clock::time_point now = Clock::now();
    if (now >= next_heartbeat) {
      message.mutable_heartbeat();
      Send(message);
      next_heartbeat = now + options_.heartbeat_interval;
      // A raised credit falls back once a whole heartbeat interval brought no job: the short batch is over, and
      // the next batch may hold long jobs, which must not pile up at one worker.
      bool idle = false;
      {
        std::lock_guard lock(mutex_);
        idle = stats_.jobs_received == jobs_at_last_heartbeat && announced_credit_ != options_.credit;
        jobs_at_last_heartbeat = stats_.jobs_received;
        if (idle) {
          short_in_a_row_ = 0;
          wanted_credit_ = options_.credit;
        }
      }
      if (idle) AnnounceCredit(options_.credit);
    }
    if (now >= broker_deadline) {
      Reconnect("no answer from the broker at " + options_.endpoint + " for " + Seconds(liveness_period));
      broker_deadline = now + liveness_period;
    }
  }
  message.mutable_disconnect()->set_reason("worker shutting down");
  Send(message);
  socket_->set(zmq::sockopt::linger, kGoodbyeLingerMs);
  socket_->close();
}

void WorkerConnection::Connect() {
  socket_ = std::make_unique<zmq::socket_t>(context_, zmq::socket_type::dealer);
  socket_->set(zmq::sockopt::linger, 0);
  socket_->set(zmq::sockopt::sndhwm, 0);  // never block the I/O thread: results and heartbeats queue instead
  socket_->set(zmq::sockopt::rcvhwm, 0);
  // A connection that failed its handshake (the broker refused our key, or it speaks CURVE and we do not) is
  // closed for good, leaving the socket without a pipe: a send must then fail at once, never block this thread.
  socket_->set(zmq::sockopt::sndtimeo, 0);
  if (curve_) {
    net::MakeCurveClient(*socket_, *curve_);
    monitor_ = std::make_unique<net::HandshakeMonitor>(context_, *socket_,
                                                         "worker-" + std::to_string(++monitors_made_));
  }
  socket_->connect(options_.endpoint);  // asynchronous: ZeroMQ keeps trying until a broker listens
  warned_bad_message_ = false;
  announced_credit_ = options_.credit;  // a new connection starts from the base credit
  {
    std::lock_guard lock(mutex_);
    ++stats_.connections;  // before READY leaves, so that whoever sees the READY sees the count
    stats_.broker_answering = false;
    stats_.credit = static_cast<std::uint32_t>(options_.credit);
    short_in_a_row_ = 0;
    wanted_credit_ = options_.credit;
  }
  v1::WorkerToBroker ready;
  ready.set_protocol_version(kProtocolVersion);
  ready.mutable_ready()->set_worker_id(worker_id_);
  ready.mutable_ready()->set_credit(static_cast<std::uint32_t>(options_.credit));
  Send(ready);
}

void WorkerConnection::AnnounceCredit(int credit) {
  v1::WorkerToBroker ready;
  ready.set_protocol_version(kProtocolVersion);
  ready.mutable_ready()->set_worker_id(worker_id_);
  ready.mutable_ready()->set_credit(static_cast<std::uint32_t>(credit));
  Send(ready);
  announced_credit_ = credit;
  std::lock_guard lock(mutex_);
  stats_.credit = static_cast<std::uint32_t>(credit);
  ++stats_.credit_changes;
}

void WorkerConnection::ReadHandshakeFailures() {
  std::vector<net::HandshakeFailure> failures = monitor_->ReadFailures();
  // A connection the broker closed early (it was stopping, say) is a reconnection, not a failed handshake.
  std::erase_if(failures, [](const net::HandshakeFailure& failure) { return failure.closed_early(); });
  {
    std::lock_guard lock(mutex_);
    stats_.handshake_failures += failures.size();
  }
  for (const net::HandshakeFailure& failure : failures) {
    const std::string why = failure.Describe();
    if (!warned_handshakes_.insert(why).second) continue;  // a handful of kinds at most
    Log("the CURVE handshake with the broker at " + options_.endpoint + " failed: " + why +
        "; is worker.pub in the broker's allowed_workers/ and broker.pub the broker's? (logged once per kind)");
  }
}

void WorkerConnection::Reconnect(const std::string& why) {
  std::size_t discarded = 0;
  {
    std::lock_guard lock(mutex_);
    discarded = jobs_.size();
    stats_.jobs_discarded += discarded;
    jobs_.clear();
  }
  if (!warned_silence_) {
    std::string line = why + "; connecting again";
    if (discarded > 0)
      line += " (dropped " + std::to_string(discarded) + " jobs not started: the broker requeues them)";
    Log(line);
    warned_silence_ = true;
  }
  socket_->close();
  Connect();
}

WorkerConnection::Heard WorkerConnection::OnBrokerMessage(const zmq::message_t& payload) {
  const proto::EnvelopeCheck check = proto::ParseEnvelope(payload.data(), payload.size(), in_);
  if (check != proto::EnvelopeCheck::kOk) {
    DropMessage(std::string(proto::Describe(check)) +
                (check == proto::EnvelopeCheck::kWrongVersion ? " " + std::to_string(in_.protocol_version()) : ""));
    return Heard::kNothing;
  }
  bool first = false;
  {
    std::lock_guard lock(mutex_);
    first = !stats_.broker_answering;
    stats_.broker_answering = true;
  }
  if (first && warned_silence_) {
    Log("the broker at " + options_.endpoint + " answers again");
    warned_silence_ = false;
  }
  switch (in_.body_case()) {
    case v1::BrokerToWorker::kJob: {
      v1::Job& job = *in_.mutable_job();
      if (job.protocol_version() != kProtocolVersion) {
        // Answer it, so that the broker gets its credit back and the client learns why.
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
        Send(answer);
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
    case v1::BrokerToWorker::BODY_NOT_SET: break;
  }
  return Heard::kAlive;
}

void WorkerConnection::DropMessage(const std::string& why) {
  {
    std::lock_guard lock(mutex_);
    ++stats_.messages_dropped;
  }
  if (warned_bad_message_) return;
  warned_bad_message_ = true;
  Log("dropped a message from the broker at " + options_.endpoint + ": " + why +
      " (further bad messages on this connection are dropped without a log line)");
}

void WorkerConnection::Send(const v1::WorkerToBroker& message) {
  out_.clear();
  message.SerializeToString(&out_);
  socket_->send(zmq::buffer(out_), zmq::send_flags::none);
}

}  // namespace orcs::worker
