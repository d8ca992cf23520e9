// The broker: takes batches of jobs from clients, hands them to workers with free credit and sends each result
// back to the client that submitted the job (docs/protocol.md). Knows nothing of physics: it links only the wire
// schema, ZeroMQ and protobuf, so it runs on a head node with no ODE.
//
// One thread runs the broker (Run() until Stop()), so tests and `orcs-batch run` embed it in-process and
// `orcs-broker` runs it as a program. This class is the ZeroMQ shell: two ROUTER sockets, polling, decoding and
// envelope checks, CURVE (ZAP and handshake monitors), and the transport the core sends through. The rules —
// queue, credit, leases, lost workers, crashes, batches, the journal — are BrokerCore's (broker_core.h), which
// the shell feeds one decoded message at a time, a tick per heartbeat interval and a Dispatch() per turn.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <string_view>
#include <vector>
#include <zmq.hpp>

#include "broker/broker_core.h"
#include "broker/broker_journal.h"
#include "broker/broker_settings.h"
#include "broker/zap_handler.h"
#include "orcs/v1/broker.pb.h"
#include "net/handshake_monitor.h"

namespace orcs::broker {

/// The broker. Construct (binds both sockets, throws std::runtime_error naming the endpoint when it cannot, and
/// net::CurveKeyError naming the file when a CURVE key is missing or malformed), call Run() on one thread,
/// Stop() from any thread.
class Broker {
 public:
  explicit Broker(BrokerOptions options);
  ~Broker();
  Broker(const Broker&) = delete;
  Broker& operator=(const Broker&) = delete;

  /// The endpoint clients connect to, e.g. "tcp://127.0.0.1:5555" (the actual port when 0 was asked for).
  const std::string& client_endpoint() const { return client_endpoint_; }
  /// The endpoint workers connect to.
  const std::string& worker_endpoint() const { return worker_endpoint_; }

  /// Serves until Stop(); then tells every worker and client it is leaving (DISCONNECT) and closes its sockets.
  /// Call once.
  void Run();
  /// Makes Run() return soon. Thread-safe and async-signal-safe; may be called before Run().
  void Stop();

  /// A snapshot of the counters, taken at the end of the broker's last loop iteration. Thread-safe.
  BrokerStats stats() const;

 private:
  using Clock = std::chrono::steady_clock;

  // CURVE.
  void EnableCurve();
  void ReadHandshakeFailures(net::HandshakeMonitor& monitor, const std::string& side);

  // Incoming traffic: frames off a socket, envelopes checked, then handed to the core.
  void ReceiveWorkerMessages(Clock::time_point now);
  void ReceiveClientMessages(Clock::time_point now);
  /// Reads one message off `socket` into frames_; false when none is waiting.
  bool ReceiveOne(zmq::socket_t& socket);
  /// Whether frames_ holds a routing id and one payload frame; drops the message (counted, logged) otherwise.
  bool OneFrame(std::string_view side, const std::string& peer);
  void OnWorkerMessage(const std::string& worker, zmq::message_t& payload, Clock::time_point now);
  void OnClientMessage(const std::string& client, zmq::message_t& payload, Clock::time_point now);

  void Log(const std::string& line) const;
  void PublishStats();

  const BrokerOptions options_;  ///< as constructed (checked by Validate)
  zmq::context_t context_;       ///< owns the sockets, the ZAP handler's and the monitors'
  zmq::socket_t client_socket_;  ///< ROUTER bound to client_endpoint_
  zmq::socket_t worker_socket_;  ///< ROUTER bound to worker_endpoint_
  std::unique_ptr<ZapHandler> zap_;                          ///< with CURVE: decides who may connect
  std::unique_ptr<net::HandshakeMonitor> client_monitor_;  ///< with CURVE: failed handshakes on client_socket_
  std::unique_ptr<net::HandshakeMonitor> worker_monitor_;  ///< with CURVE: failed handshakes on worker_socket_
  std::set<std::string> warned_handshakes_;                  ///< kinds of handshake failure logged already
  std::uint64_t handshakes_failed_ = 0;                      ///< BrokerStats::handshakes_failed
  std::string client_endpoint_;  ///< where client_socket_ is bound, with the real port
  std::string worker_endpoint_;  ///< where worker_socket_ is bound, with the real port
  int wake_fd_ = -1;  ///< eventfd Stop() writes to, so that a blocked poll returns
  std::unique_ptr<BrokerJournal> journal_;      ///< null without BrokerOptions::journal
  std::unique_ptr<BrokerTransport> transport_;  ///< the core's sends, onto the two sockets
  std::unique_ptr<BrokerCore> core_;            ///< the rules and the state
  std::atomic<bool> stop_requested_{false};  ///< set by Stop(), read by Run()
  bool ran_ = false;                         ///< Run() was called: it may be called once

  v1::WorkerToBroker worker_in_;        ///< reused for parsing
  v1::ClientToBroker client_in_;        ///< reused for parsing
  std::vector<zmq::message_t> frames_;  ///< reused for receiving

  mutable std::mutex stats_mutex_;
  BrokerStats stats_;  ///< the last published snapshot (guarded by stats_mutex_)
};

}  // namespace orcs::broker
