// The reconnecting DEALER connection both peers of the broker use (docs/protocol.md, "Heartbeats and liveness"):
// BatchClient (clients/runtime/batch_client.h) and WorkerConnection (worker/broker_connection.h). It owns what the two have in
// common — the socket and its options, CURVE and the handshake monitor, connecting again, the heartbeat clock,
// the broker's liveness, polling with a deadline and a wake-up, raw frames in and out, and the log lines about
// silence and dropped messages — and knows nothing of the messages: each side builds and reads its own envelopes
// (net/envelope_check.h) and decides what to send again after a reconnection.
//
// Threads: Wake() may be called from any thread; everything else belongs to the one I/O thread that polls.
#pragma once

#include <chrono>
#include <cstddef>
#include <functional>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <zmq.hpp>

#include "net/curve_keys.h"
#include "net/handshake_monitor.h"
#include "proto/envelope.h"

namespace orcs::net {

/// What a DealerConnection connects to, who it is and how it paces itself.
struct DealerConnectionOptions {
  /// The broker endpoint, e.g. "tcp://127.0.0.1:5555".
  std::string endpoint;
  /// "client" or "worker": names the CURVE key files (<role>.key, <role>.pub), the handshake monitors and the
  /// broker folder of allowed keys in log hints (allowed_<role>s/).
  std::string role;
  /// Prefixes the constructor's errors, e.g. "BatchClient".
  std::string owner;
  /// Folder of CURVE keys (docs/security.md); "" = plain TCP.
  std::string curve_keys;
  /// How often a heartbeat leaves while the connection is in use (ms, positive).
  std::chrono::milliseconds heartbeat_interval{1000};
  /// The broker silent for this many heartbeat intervals counts as lost (at least 2).
  int liveness = 5;
  /// The serialised HEARTBEAT envelope of the side (a ClientToBroker or WorkerToBroker), sent as one frame.
  std::string heartbeat;
  /// Where connection events go, one line each without a newline. Must be set.
  std::function<void(const std::string&)> log;
};

/// The options of one side (`side`: BatchClientOptions or WorkerConnectionOptions, whose endpoint, curve_keys,
/// heartbeat_interval and liveness it copies). Its heartbeat is an empty HEARTBEAT `Envelope` (ClientToBroker or
/// WorkerToBroker) of this build's protocol version.
template <typename Envelope, typename SideOptions>
DealerConnectionOptions DealerOptionsFor(const SideOptions& side, std::string role, std::string owner,
                                         std::function<void(const std::string&)> log) {
  Envelope heartbeat;
  heartbeat.set_protocol_version(proto::kProtocolVersion);
  heartbeat.mutable_heartbeat()->set_interval_ms(static_cast<std::uint32_t>(side.heartbeat_interval.count()));
  DealerConnectionOptions dealer;
  dealer.endpoint = side.endpoint;
  dealer.role = std::move(role);
  dealer.owner = std::move(owner);
  dealer.curve_keys = side.curve_keys;
  dealer.heartbeat_interval = side.heartbeat_interval;
  dealer.liveness = side.liveness;
  dealer.heartbeat = heartbeat.SerializeAsString();
  dealer.log = std::move(log);
  return dealer;
}

/// One reconnecting DEALER socket to the broker, with its heartbeat clock and the broker's liveness.
class DealerConnection {
 public:
  using Clock = std::chrono::steady_clock;

  /// What the next message on the socket was.
  enum class Received {
    kNone,       ///< nothing waiting (or no socket)
    kFrame,      ///< one single-frame message, in the caller's frame
    kMultipart,  ///< a message of several frames, read and dropped whole (the protocol has one frame a message)
  };

  /// What one Poll() saw.
  struct PollEvents {
    bool readable = false;              ///< the socket has messages to Receive()
    std::size_t handshakes_refused = 0;  ///< CURVE handshakes that failed since the last Poll (count, for stats)
  };

  /// Loads the CURVE keys (net::CurveKeyError naming the file) and checks that ZeroMQ can parse the endpoint
  /// (std::invalid_argument "<owner>: cannot connect to '<endpoint>': ..."). Opens no connection yet.
  explicit DealerConnection(DealerConnectionOptions options);
  ~DealerConnection();
  DealerConnection(const DealerConnection&) = delete;
  DealerConnection& operator=(const DealerConnection&) = delete;

  /// Thread-safe: makes a Poll() in progress (or the next one) return at once.
  void Wake();

  /// Opens a new socket (CURVE and its monitor when keys were given) and starts connecting: asynchronous, ZeroMQ
  /// keeps trying until a broker listens. Throws std::runtime_error when ZeroMQ refuses the endpoint.
  void Open();
  /// Closes the socket, dropping whatever was queued on it.
  void Close();
  /// Close() and Open(): a new connection, so that a restarted broker sees a new peer. Logs nothing.
  void Reopen();
  /// Whether a socket is open.
  bool is_open() const { return socket_ != nullptr; }

  /// Waits until the socket is readable, Wake() is called, a handshake fails or `wake_at` passes (nullopt = no
  /// deadline). A signal interrupting the wait is a return with nothing seen.
  PollEvents Poll(std::optional<Clock::time_point> wake_at);
  /// The next message, without blocking.
  Received Receive(zmq::message_t& frame);
  /// Reads every waiting message without blocking: each single frame goes to `on_frame`, which returns false to
  /// stop reading (it replaced the socket); a message of several frames is dropped whole and named to
  /// `on_dropped`.
  void ReceiveAll(const std::function<bool(const zmq::message_t&)>& on_frame,
                  const std::function<void(const std::string&)>& on_dropped);
  /// Sends one frame; never blocks (a socket without a connection drops it). Needs an open socket.
  void Send(std::string_view frame);
  /// Serialises a protobuf message and sends it as one frame.
  template <typename Message>
  void SendMessage(const Message& message) {
    out_.clear();
    message.SerializeToString(&out_);
    Send(out_);
  }
  /// Sends `frame` (the side's DISCONNECT), gives it kGoodbyeLingerMs to leave and closes the socket.
  void SendGoodbye(std::string_view frame);

  /// Starts the heartbeat clock over: the next heartbeat is due one interval after `now`.
  void ScheduleHeartbeat(Clock::time_point now);
  /// Sends the heartbeat when it is due at `now` and schedules the next; true when one was sent.
  bool HeartbeatIfDue(Clock::time_point now);
  /// When the next heartbeat is due.
  Clock::time_point next_heartbeat() const { return next_heartbeat_; }

  /// A valid message came: the broker is alive. Logs "answers again" after ReportSilence().
  void MarkHeard();
  /// This process did not run for `gap` (it was stopped: SIGSTOP, a suspended laptop, a debugger): the broker's
  /// silence during it is not the broker's, so the liveness clocks move on by `gap` and the next heartbeat is due
  /// now. Without this a client woken after 35 s gave up at once without asking the broker once.
  void ExcuseAbsence(Clock::duration gap);
  /// When the broker was last heard (the epoch when never).
  Clock::time_point last_heard() const { return last_heard_; }
  /// When the broker counts as lost: one liveness period after it was last heard or the socket opened, whichever
  /// is later.
  Clock::time_point liveness_deadline() const;
  /// The broker's heartbeat said it beats every `interval` (0 = not said): the liveness period follows the slower
  /// of the two sides, up to a minute, so that a broker slower than this side is not taken for dead.
  void NotePeerInterval(std::chrono::milliseconds interval);
  /// The liveness period: liveness × the longer of this side's heartbeat interval and the broker's.
  Clock::duration liveness_period() const {
    return std::max(options_.heartbeat_interval, peer_interval_) * options_.liveness;
  }

  /// Logs why the connection starts over, once until the broker answers again (a dead broker is one line).
  void ReportSilence(const std::string& line);
  /// Logs a message dropped for `why`, once per connection (a flood of bad frames is one line).
  void ReportDropped(const std::string& why);
  /// Why the last handshake failed, in words ("" when none did): explains a broker that never answers.
  const std::string& last_handshake_failure() const { return last_handshake_failure_; }

  /// How long a goodbye may take to leave the closing socket.
  static constexpr int kGoodbyeLingerMs = 200;

 private:
  void CheckEndpoint();
  void DrainWakeups();
  std::size_t ReadHandshakeFailures();

  const DealerConnectionOptions options_;
  std::optional<CurvePeerKeys> curve_;  ///< set: every connection uses CURVE with these keys
  zmq::context_t context_;              ///< before the sockets, which must close before it ends
  int wake_fd_ = -1;                    ///< eventfd that Wake() writes and Poll() watches
  std::unique_ptr<zmq::socket_t> socket_;
  std::unique_ptr<HandshakeMonitor> monitor_;  ///< with CURVE: failed handshakes of socket_
  int monitors_made_ = 0;                      ///< names each monitor uniquely within context_
  std::string last_handshake_failure_;         ///< HandshakeFailure::Describe() of the last failure
  std::set<std::string> warned_handshakes_;    ///< kinds of handshake failure logged already
  Clock::time_point next_heartbeat_;           ///< when the next heartbeat is due
  Clock::time_point last_heard_;               ///< when a valid message last came (epoch: never)
  Clock::time_point last_open_;                ///< when the current socket was opened
  bool warned_bad_message_ = false;            ///< a dropped message was logged on this socket
  bool warned_silence_ = false;                ///< ReportSilence() logged and the broker has not answered since
  std::string out_;                            ///< SendMessage()'s buffer, reused
  std::chrono::milliseconds peer_interval_{0};  ///< NotePeerInterval(): the broker's heartbeat interval
};

}  // namespace orcs::net
