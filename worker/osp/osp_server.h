// The OSP 1.1 server (docs/spec/osp.md, docs/osp.md): old ORCS and NERD clients drive a live simulation
// step by step over UDP. One thread runs it (Run() until Stop()). It is a state machine of small handlers, one
// per command (OnInit, OnEventId, ..., OnStep, OnTakeControl), plus a tick that drops silent clients.
//
// A client says INIT to the server port and gets its own handler socket (a new ephemeral port, connected to
// it), which all its further traffic uses. Synchronised stepping: one physics step runs only when every client
// that controls an agent has sent inputs for each of its agents; then each gets its agents' outputs. Reset with a
// seed waits likewise for every controlling client. A controlling client the others wait for (its step or reset
// is missing) that stays silent for longer than client_timeout loses its agents, so the others are not blocked
// for ever; a client that merely waits for the others is never dropped. Every datagram is checked: anything short, unknown or not
// allowed is ignored (counted and logged once per client), never a crash or a block.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "base/log_sink.h"
#include "model/scene/simulation.h"
#include "worker/osp/agent_interface.h"
#include "worker/osp/osp_datagram.h"
#include "worker/osp/udp_socket.h"

namespace orcs::osp {

struct OspServerOptions {
  std::string bind_address = "127.0.0.1";  ///< interface to listen on; loopback unless told otherwise
  std::uint16_t port = 45454;              ///< the server port (/UDPCommunication/ServerPort); 0 = ephemeral
  /// A controlling client the others wait for, silent this long (no datagram at all, counted from when the
  /// waiting began at the earliest), is dropped and loses its agents. A client that sends nothing to its handler
  /// port this long after its INIT never completed the handshake and is dropped too; and when every slot is
  /// taken, an INIT takes the slot of the client silent longest, if it has been silent this long.
  std::chrono::milliseconds client_timeout{10000};
  /// Clients served at once. An INIT beyond them is ignored (unless a silent client's slot can be reclaimed, as
  /// above), so that a flood of INITs cannot use up the process's sockets (each client has its own) and end the
  /// server.
  int max_clients = 64;
  /// The server port logs the first ignored datagram of each sender address (at most kMaxLoggedSenders of them)
  /// and counts the rest; one line this often gives the count, when there was any. A flood of garbage on the server
  /// port costs a few lines, as on the handler ports (docs/osp.md, "Malformed datagrams").
  std::chrono::milliseconds server_log_summary_interval{10000};
  /// Where log lines go (one event each, no newline); empty = stderr, prefixed "orcs-osp: ".
  LogSink log;
  /// Called before each step with the simulated time (s), before the clients' inputs are written, so that
  /// what it writes (the -play records) a client's finite inputs override. Empty = nothing.
  std::function<void(double time)> before_step;
  /// Called after each step the clients' inputs ran (the --record frames). Empty = nothing.
  std::function<void()> after_step;
  /// Called after each simulation reset (70). Empty = nothing.
  std::function<void()> after_reset;
};

/// Counters of a running server, for tests and logs. They only grow, but for `clients`.
struct OspServerStats {
  int clients = 0;                       ///< connected clients now
  std::uint64_t steps = 0;               ///< physics steps run
  std::uint64_t resets = 0;              ///< simulation resets
  std::uint64_t datagrams_ignored = 0;   ///< malformed, unknown or not allowed
  std::uint64_t clients_timed_out = 0;   ///< clients dropped for silence while others waited for them
  std::uint64_t clients_reclaimed = 0;   ///< slots taken back: no handshake, a closed port, or silent when full
};

/// Something else served in the same thread (the ODCP servers): its socket is polled with the server's.
class DatagramService {
 public:
  virtual ~DatagramService() = default;
  virtual int fd() const = 0;
  /// The socket is readable: take what is waiting.
  virtual void OnReadable() = 0;
};

class OspServer {
 public:
  /// Binds the server port. `simulation` must be built; it is stepped and reset only by this server's thread.
  /// Throws std::runtime_error when the port cannot be bound.
  OspServer(scene::Simulation& simulation, OspServerOptions options);
  ~OspServer();
  OspServer(const OspServer&) = delete;
  OspServer& operator=(const OspServer&) = delete;

  /// The server port's address (the actual port when 0 was asked for).
  Endpoint endpoint() const { return server_socket_.local(); }
  /// Serves until Stop().
  void Run();
  /// Makes Run() return; safe from any thread and from a signal handler.
  void Stop();
  /// A snapshot of the counters (any thread).
  OspServerStats stats() const;
  /// Serves `service` in this thread too (before Run()).
  void AddService(DatagramService* service) { services_.push_back(service); }

  /// Handles one datagram as Run() does with what it receives: on the server port when `session` is 0, else on
  /// client `session`'s handler socket (clients are numbered from 1 as they connect; an unknown one is ignored).
  /// For tests and the fuzzer, which drive the server without polling. Not while Run() runs.
  void Deliver(int session, const Datagram& datagram);

 private:
  using Clock = std::chrono::steady_clock;

  // One connected client.
  struct Session {
    Session(int session_id, UdpSocket handler, Endpoint address, Clock::time_point now)
        : id(session_id), socket(std::move(handler)), peer(address), last_heard(now) {}
    int id = 0;                          // for logs
    UdpSocket socket;                    // its handler socket, connected to it
    Endpoint peer;                       // its address
    Clock::time_point last_heard;        // when it last sent anything (its INIT, until it speaks on its port)
    bool spoke = false;                  // sent anything to its handler port: the handshake is complete
    std::set<int> agents;                // agent indices it controls
    std::set<int> observed_events;       // event indices it observes
    std::set<int> observed_values;       // repository ids it observes
    std::map<int, std::vector<float>> step_inputs;  // agent index → normalised inputs for the next step
    bool reset_requested = false;        // sent 70, waiting for the reset
    std::int32_t reset_seed = 0;         // the seed it asked for
    bool warned = false;                 // an ignored datagram was logged for it
    bool values_overflow_logged = false; // said once that its observed values overflow the step reply
  };

  // One observed value as a step reply carries it.
  struct ObservedValue {
    std::int32_t id;   // wire value id
    std::string text;  // its printed form, as 51 sends it
  };

  void ServeOnce();
  void OnServerDatagram(const Datagram& datagram);
  void OnSessionDatagram(Session& session, const Datagram& datagram);
  void Dispatch(Session& session, std::uint8_t command, DatagramReader& reader);
  void OnTick();

  // Handlers, one per command (spec order).
  void OnEnd(Session& session);
  void OnResetCommunication(Session& session);
  void OnEventId(Session& session, DatagramReader& reader);
  void OnObserveEvent(Session& session, DatagramReader& reader);
  void OnValueIds(Session& session, DatagramReader& reader);
  void OnGetValue(Session& session, DatagramReader& reader);
  void OnSetValue(Session& session, DatagramReader& reader);
  void OnObserveValues(Session& session, DatagramReader& reader, bool observe);
  void OnResetSimulation(Session& session, DatagramReader& reader);
  void OnStep(Session& session, DatagramReader& reader);
  std::vector<ObservedValue> ObservedValues(Session& session, std::size_t room);
  void OnAgentOverview(Session& session);
  void OnAgentInfo(Session& session, DatagramReader& reader);
  void OnTakeControl(Session& session, DatagramReader& reader);
  void OnReleaseControl(Session& session, DatagramReader& reader);

  // What happens when every controlling client is ready.
  void StepIfEveryoneIsReady();
  void ResetIfEveryoneAsked();
  void RunStep();
  void SendStepResults();

  void Send(Session& session, const DatagramWriter& writer);
  void Ignore(Session* session, const std::string& why);
  void IgnoreOnServerPort(const Endpoint& from, const std::string& why);
  void SummariseServerPort(Clock::time_point now, bool final);  // the count line, when due (or at the end)
  void DropSession(int id, const std::string& why);
  void ReclaimSession(int id, const std::string& why);  // DropSession, counted as reclaimed
  bool ReclaimSilentSlot();  // when full: drops the client silent longest, if silent for client_timeout
  int ControllerOf(int agent) const;  // session id, or 0
  bool BlocksOthers(const Session& session) const;
  bool AnythingPending() const;  // a step input or reset request is waiting for others  // a controller whose step or reset the others wait for
  int AgentIndexOf(std::int32_t agent_id) const;  // −1 for an unknown id
  void Log(const std::string& line) const;

  scene::Simulation& simulation_;
  const OspServerOptions options_;
  UdpSocket server_socket_;
  int wake_fd_ = -1;  // eventfd: Stop() wakes the poll through it
  std::vector<AgentInterface> agents_;
  std::map<int, std::unique_ptr<Session>> sessions_;  // by session id
  int next_session_id_ = 1;
  Clock::time_point waiting_since_;  // when the first step or reset of the current round arrived
  std::vector<DatagramService*> services_;

  // The server port's log bound: senders whose first ignored datagram was logged, and what went unlogged since the
  // last count line.
  static constexpr std::size_t kMaxLoggedSenders = 64;
  std::set<std::pair<std::uint32_t, std::uint16_t>> logged_senders_;
  std::uint64_t unlogged_ignored_ = 0;
  std::set<std::pair<std::uint32_t, std::uint16_t>> unlogged_senders_;  // of those, at most kMaxLoggedSenders + 1
  Clock::time_point last_summary_ = Clock::now();

  mutable std::mutex stats_mutex_;
  OspServerStats stats_;
};

}  // namespace orcs::osp
