#include "net/dealer_connection.h"

#include <sys/eventfd.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cerrno>
#include <cstdint>
#include <stdexcept>
#include <utility>
#include <vector>

namespace orcs::net {

DealerConnection::DealerConnection(DealerConnectionOptions options) : options_(std::move(options)), context_(1) {
  if (!options_.curve_keys.empty()) curve_ = LoadCurvePeerKeys(options_.curve_keys, options_.role);
  CheckEndpoint();
  wake_fd_ = ::eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
  if (wake_fd_ < 0) throw std::runtime_error(options_.owner + ": eventfd failed");
}

DealerConnection::~DealerConnection() {
  monitor_.reset();
  socket_.reset();
  ::close(wake_fd_);
}

// A malformed endpoint fails in the constructor, at once, rather than later in the I/O thread.
void DealerConnection::CheckEndpoint() {
  try {
    zmq::socket_t probe(context_, zmq::socket_type::dealer);
    probe.set(zmq::sockopt::linger, 0);
    probe.connect(options_.endpoint);
  } catch (const zmq::error_t& error) {
    throw std::invalid_argument(options_.owner + ": cannot connect to '" + options_.endpoint + "': " + error.what());
  }
}

void DealerConnection::Wake() {
  const std::uint64_t one = 1;
  [[maybe_unused]] const ssize_t written = ::write(wake_fd_, &one, sizeof one);
}

void DealerConnection::DrainWakeups() {
  std::uint64_t count = 0;
  [[maybe_unused]] const ssize_t read = ::read(wake_fd_, &count, sizeof count);
}

void DealerConnection::Open() {
  monitor_.reset();
  socket_ = std::make_unique<zmq::socket_t>(context_, zmq::socket_type::dealer);
  socket_->set(zmq::sockopt::linger, 0);
  socket_->set(zmq::sockopt::sndhwm, 0);  // never block the I/O thread: messages queue instead
  socket_->set(zmq::sockopt::rcvhwm, 0);  // never make the broker hold messages back
  // A connection that failed its handshake (the broker refused our key, or it speaks CURVE and we do not) is
  // closed for good, leaving the socket without a pipe: a send must then fail at once, never block this thread.
  socket_->set(zmq::sockopt::sndtimeo, 0);
  if (curve_) {
    MakeCurveClient(*socket_, *curve_);
    monitor_ = std::make_unique<HandshakeMonitor>(context_, *socket_,
                                                  options_.role + "-" + std::to_string(++monitors_made_));
  }
  try {
    socket_->connect(options_.endpoint);
  } catch (const zmq::error_t& error) {
    throw std::runtime_error("cannot connect to " + options_.endpoint + ": " + error.what());
  }
  last_open_ = Clock::now();
  warned_bad_message_ = false;
}

void DealerConnection::Close() {
  monitor_.reset();
  if (socket_) socket_->close();
  socket_.reset();
}

void DealerConnection::Reopen() {
  Close();
  Open();
}

DealerConnection::PollEvents DealerConnection::Poll(std::optional<Clock::time_point> wake_at) {
  std::chrono::milliseconds wait{-1};  // -1: no deadline
  if (wake_at) {
    const Clock::duration left = std::max(*wake_at - Clock::now(), Clock::duration{});
    wait = std::chrono::ceil<std::chrono::milliseconds>(left);
  }
  zmq::pollitem_t items[] = {{nullptr, wake_fd_, ZMQ_POLLIN, 0},
                             {socket_ ? socket_->handle() : nullptr, 0, ZMQ_POLLIN, 0},
                             {monitor_ ? monitor_->socket().handle() : nullptr, 0, ZMQ_POLLIN, 0}};
  try {
    zmq::poll(items, !socket_ ? 1 : monitor_ ? 3 : 2, wait);
  } catch (const zmq::error_t& error) {
    if (error.num() != EINTR) throw;
    return {};
  }
  PollEvents events;
  if (items[0].revents & ZMQ_POLLIN) DrainWakeups();
  if (socket_ && monitor_ && (items[2].revents & ZMQ_POLLIN)) events.handshakes_refused = ReadHandshakeFailures();
  events.readable = socket_ && (items[1].revents & ZMQ_POLLIN);
  return events;
}

// Returns the number of refusals; logs each kind once.
std::size_t DealerConnection::ReadHandshakeFailures() {
  std::vector<HandshakeFailure> failures = monitor_->ReadFailures();
  // A connection the broker closed early (it was stopping, or it speaks plain TCP and noticed first) is no
  // refusal to count or log, but it may explain a broker that never answers.
  for (const HandshakeFailure& failure : failures) last_handshake_failure_ = failure.Describe();
  std::erase_if(failures, [](const HandshakeFailure& failure) { return failure.closed_early(); });
  for (const HandshakeFailure& failure : failures) {
    const std::string why = failure.Describe();
    if (!warned_handshakes_.insert(why).second) continue;  // a handful of kinds at most
    options_.log("the CURVE handshake with the broker at " + options_.endpoint + " failed: " + why + "; is " +
                 options_.role + ".pub in the broker's allowed_" + options_.role + "s/ and broker.pub the broker's?" +
                 " (logged once per kind)");
  }
  return failures.size();
}

DealerConnection::Received DealerConnection::Receive(zmq::message_t& frame) {
  if (!socket_ || !socket_->recv(frame, zmq::recv_flags::dontwait)) return Received::kNone;
  if (!frame.more()) return Received::kFrame;
  while (frame.more() && socket_->recv(frame, zmq::recv_flags::dontwait)) {
  }
  return Received::kMultipart;
}

void DealerConnection::ReceiveAll(const std::function<bool(const zmq::message_t&)>& on_frame,
                                  const std::function<void(const std::string&)>& on_dropped) {
  zmq::message_t frame;
  while (true) {
    const Received received = Receive(frame);
    if (received == Received::kNone) return;
    if (received == Received::kMultipart) {
      on_dropped("a message of several frames");
      continue;
    }
    if (!on_frame(frame)) return;
  }
}

void DealerConnection::Send(std::string_view frame) {
  socket_->send(zmq::buffer(frame), zmq::send_flags::none);
}

void DealerConnection::SendGoodbye(std::string_view frame) {
  Send(frame);
  socket_->set(zmq::sockopt::linger, kGoodbyeLingerMs);
  Close();
}

void DealerConnection::ScheduleHeartbeat(Clock::time_point now) { next_heartbeat_ = now + options_.heartbeat_interval; }

bool DealerConnection::HeartbeatIfDue(Clock::time_point now) {
  if (now < next_heartbeat_) return false;
  Send(options_.heartbeat);
  ScheduleHeartbeat(now);
  return true;
}

void DealerConnection::NotePeerInterval(std::chrono::milliseconds interval) {
  peer_interval_ = std::min<std::chrono::milliseconds>(interval, std::chrono::minutes(1));
}

void DealerConnection::MarkHeard() {
  last_heard_ = Clock::now();
  if (!warned_silence_) return;
  options_.log("the broker at " + options_.endpoint + " answers again");
  warned_silence_ = false;
}

void DealerConnection::ExcuseAbsence(Clock::duration gap) {
  if (last_heard_ != Clock::time_point{}) last_heard_ += gap;
  last_open_ += gap;
  next_heartbeat_ = Clock::now();
  options_.log("this process did not run for " + std::to_string(std::lround(std::chrono::duration<double>(gap).count())) +
               " s (stopped?): asking the broker at " + options_.endpoint + " again before judging it");
}

DealerConnection::Clock::time_point DealerConnection::liveness_deadline() const {
  return std::max(last_heard_, last_open_) + liveness_period();
}

void DealerConnection::ReportSilence(const std::string& line) {
  if (warned_silence_) return;
  options_.log(line);
  warned_silence_ = true;
}

void DealerConnection::ReportDropped(const std::string& why) {
  if (warned_bad_message_) return;
  warned_bad_message_ = true;
  options_.log("dropped a message from the broker at " + options_.endpoint + ": " + why +
               " (further bad messages on this connection are dropped without a log line)");
}

}  // namespace orcs::net
