// The ZeroMQ shell around BrokerCore: binds and polls the two ROUTER sockets, checks every frame and envelope
// before the core sees it, runs CURVE's ZAP handler and handshake monitors, groups each turn's journal writes into
// one transaction, and sends what the core says through ZmqTransport.
#include "broker/broker.h"

#include <sys/eventfd.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <iterator>
#include <stdexcept>
#include <vector>
#include <zmq_addon.hpp>

#include "base/demand.h"
#include "broker/broker_text.h"
#include "net/envelope_check.h"
#include "proto/envelope.h"

namespace orcs::broker {
namespace {

using proto::kProtocolVersion;

constexpr std::int64_t kMaxMessageBytes = 1 << 29;  // 512 MiB: larger messages close the sender's connection
constexpr int kMaxMessagesPerRound = 256;           // per socket and loop iteration, so neither side starves
constexpr int kCloseLingerMs = 200;                 // how long DISCONNECTs may take to leave when closing
constexpr std::size_t kMaxWarnedHandshakes = 4096;  // bound on the "logged once" set of handshake failures

// The core's messages onto the ROUTER sockets. router_mandatory makes a send to a vanished peer fail with
// EHOSTUNREACH, which the core reads as "the peer's connection is gone".
class ZmqTransport final : public BrokerTransport {
 public:
  ZmqTransport(zmq::socket_t& workers, zmq::socket_t& clients) : workers_(workers), clients_(clients) {}

  bool SendToWorker(const std::string& worker, const v1::BrokerToWorker& message) override {
    return Send(workers_, worker, message);
  }
  bool SendToClient(const std::string& client, const v1::BrokerToClient& message) override {
    return Send(clients_, client, message);
  }

 private:
  bool Send(zmq::socket_t& socket, const std::string& peer, const google::protobuf::Message& message) {
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

  zmq::socket_t& workers_;  ///< the worker ROUTER socket
  zmq::socket_t& clients_;  ///< the client ROUTER socket
  std::string out_;         ///< reused for serialising
};

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
  if (!options_.journal.empty()) journal_ = std::make_unique<BrokerJournal>(options_.journal);
  transport_ = std::make_unique<ZmqTransport>(worker_socket_, client_socket_);
  core_ = std::make_unique<BrokerCore>(options_, *transport_, journal_.get());
  core_->SetWorkerEndpoint(worker_endpoint_);
  core_->Restore(Clock::now());
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
    ++handshakes_failed_;
    // Refusals are logged by the ZAP handler, with the key; early closes are routine (scans, endpoint checks).
    if (failure.event == ZMQ_EVENT_HANDSHAKE_FAILED_AUTH || failure.closed_early()) continue;
    const std::string why = failure.Describe();
    if (warned_handshakes_.size() < kMaxWarnedHandshakes && warned_handshakes_.insert(side + why).second) {
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
  ORCS_DEMAND_MSG(!ran_, "Broker::Run called twice");
  ran_ = true;
  Clock::time_point next_tick = Clock::now() + options_.heartbeat_interval;
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
    const Clock::time_point received_at = Clock::now();
    if (items[0].revents & ZMQ_POLLIN) ReceiveWorkerMessages(received_at);
    if (items[1].revents & ZMQ_POLLIN) ReceiveClientMessages(received_at);
    const Clock::time_point now = Clock::now();
    if (now >= next_tick) {
      core_->OnTick(now);
      next_tick = now + options_.heartbeat_interval;
    }
    core_->Dispatch(now);
    if (journal_) journal_->Commit();
    PublishStats();
  }
  core_->SayGoodbye();
  PublishStats();
  client_socket_.close();
  worker_socket_.close();
}

// ---------------------------------------------------------------------------------------------------------------
// Incoming traffic

bool Broker::ReceiveOne(zmq::socket_t& socket) {
  frames_.clear();
  return zmq::recv_multipart(socket, std::back_inserter(frames_), zmq::recv_flags::dontwait).has_value();
}

bool Broker::OneFrame(std::string_view side, const std::string& peer) {
  if (frames_.size() == 2) return true;
  core_->DropMessage(side, peer, "expected one frame, got " + std::to_string(frames_.size() - 1));
  return false;
}

void Broker::ReceiveWorkerMessages(Clock::time_point now) {
  for (int i = 0; i < kMaxMessagesPerRound && ReceiveOne(worker_socket_); ++i) {
    const std::string worker = frames_[0].to_string();
    if (OneFrame("worker", worker)) OnWorkerMessage(worker, frames_[1], now);
  }
}

void Broker::ReceiveClientMessages(Clock::time_point now) {
  for (int i = 0; i < kMaxMessagesPerRound && ReceiveOne(client_socket_); ++i) {
    const std::string client = frames_[0].to_string();
    if (OneFrame("client", client)) OnClientMessage(client, frames_[1], now);
  }
}

void Broker::OnWorkerMessage(const std::string& worker, zmq::message_t& payload, Clock::time_point now) {
  const proto::EnvelopeCheck check = proto::ParseEnvelope(payload.data(), payload.size(), worker_in_);
  if (check != proto::EnvelopeCheck::kOk) {
    core_->DropMessage("worker", worker, net::DescribeRejection(check, worker_in_.protocol_version()));
    return;
  }
  core_->OnWorkerMessage(worker, worker_in_, now);
}

void Broker::OnClientMessage(const std::string& client, zmq::message_t& payload, Clock::time_point now) {
  const proto::EnvelopeCheck check = proto::ParseEnvelope(payload.data(), payload.size(), client_in_);
  if (check != proto::EnvelopeCheck::kOk) {
    core_->DropMessage("client", client, net::DescribeRejection(check, client_in_.protocol_version()));
    return;
  }
  // With CURVE, the ZAP handler named the sender's key as its User-Id: the key a batch belongs to.
  const char* key = zap_ ? zmq_msg_gets(payload.handle(), "User-Id") : nullptr;
  core_->OnClientMessage(client, key != nullptr ? key : "", client_in_, now);
}

// ---------------------------------------------------------------------------------------------------------------
// Bookkeeping

void Broker::Log(const std::string& line) const { WriteLog(options_.log, line); }

void Broker::PublishStats() {
  BrokerStats snapshot = core_->Stats();
  snapshot.handshakes_failed = handshakes_failed_;
  if (zap_) snapshot.handshakes_refused = zap_->stats().refused;
  std::lock_guard lock(stats_mutex_);
  stats_ = snapshot;
}

}  // namespace orcs::broker
