#include "worker/osp/osp_server.h"

#include "base/log_sink.h"
#include "worker/osp/protocol_values.h"

#include <poll.h>
#include <sys/eventfd.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <optional>

#include "model/core/error.h"
#include "worker/osp/osp_protocol.h"
#include "worker/osp/protocol_values.h"

namespace orcs::osp {
namespace {

// How often silent clients are looked for, and how long one poll waits at most.
constexpr int kTickMilliseconds = 100;
// Bytes of a step result before its outputs and events: code, agentId, nOut, nInfo, nEvents, 0.
constexpr std::size_t kStepResultHeaderBytes = 1 + 5 * 4;

// Wire ids count from 1, so that 0 can mean "unknown" where the protocol says so.
std::int32_t WireId(int index) { return static_cast<std::int32_t>(index) + 1; }

DatagramWriter Reply(Command command) {
  DatagramWriter writer;
  writer.Byte(command);
  return writer;
}

}  // namespace

OspServer::OspServer(scene::Simulation& simulation, OspServerOptions options)
    : simulation_(simulation), options_(std::move(options)), server_socket_(options_.bind_address, options_.port) {
  wake_fd_ = eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
  if (wake_fd_ < 0) throw std::runtime_error("cannot create an eventfd");
  for (int a = 0; a < simulation_.agent_count(); ++a) agents_.push_back(MakeAgentInterface(simulation_, a));
}

OspServer::~OspServer() { close(wake_fd_); }

void OspServer::Stop() {
  const std::uint64_t one = 1;
  [[maybe_unused]] const ssize_t written = write(wake_fd_, &one, sizeof one);
}

OspServerStats OspServer::stats() const {
  std::lock_guard lock(stats_mutex_);
  return stats_;
}

void OspServer::Log(const std::string& line) const {
  WriteLogLine(options_.log, "orcs-osp", line);
}

void OspServer::Run() {
  Log("OSP 1.1 server on " + endpoint().ToString() + ", " + std::to_string(agents_.size()) + " agents");
  for (;;) {
    std::vector<pollfd> fds = {{wake_fd_, POLLIN, 0}, {server_socket_.fd(), POLLIN, 0}};
    std::vector<int> session_ids;
    for (const auto& [id, session] : sessions_) {
      fds.push_back({session->socket.fd(), POLLIN, 0});
      session_ids.push_back(id);
    }
    for (DatagramService* service : services_) fds.push_back({service->fd(), POLLIN, 0});
    poll(fds.data(), fds.size(), kTickMilliseconds);
    if (fds[0].revents & POLLIN) return SummariseServerPort(Clock::now(), true);
    if (fds[1].revents & POLLIN) {
      while (std::optional<Datagram> datagram = server_socket_.Receive()) OnServerDatagram(*datagram);
    }
    for (std::size_t i = 0; i < session_ids.size(); ++i) {
      if (fds[2 + i].revents & POLLERR) {  // else poll() reports it again at once, for ever
        auto it = sessions_.find(session_ids[i]);
        if (it != sessions_.end() && it->second->socket.TakeError() == ECONNREFUSED) {
          ReclaimSession(session_ids[i], "is gone (its port is closed: ICMP port unreachable)");
          continue;
        }
      }
      if ((fds[2 + i].revents & POLLIN) == 0) continue;
      auto it = sessions_.find(session_ids[i]);
      while (it != sessions_.end()) {  // a handler may drop the session (or all of them)
        std::optional<Datagram> datagram = it->second->socket.Receive();
        if (!datagram) break;
        OnSessionDatagram(*it->second, *datagram);
        it = sessions_.find(session_ids[i]);
      }
    }
    for (std::size_t s = 0; s < services_.size(); ++s) {
      if (fds[2 + session_ids.size() + s].revents & POLLIN) services_[s]->OnReadable();
    }
    OnTick();
  }
}

void OspServer::Deliver(int session, const Datagram& datagram) {
  if (session == 0) return OnServerDatagram(datagram);
  const auto it = sessions_.find(session);
  if (it != sessions_.end()) OnSessionDatagram(*it->second, datagram);
}

// ---------------------------------------------------------------------------------------------------------
// The server port: only INIT.

void OspServer::OnServerDatagram(const Datagram& datagram) {
  try {
    DatagramReader reader(datagram.bytes);
    if (reader.Byte() != kInit || reader.Byte() != kMajorVersion || reader.Byte() != kMinorVersion) {
      return IgnoreOnServerPort(datagram.from, "a datagram on the server port that is not INIT 1.1");
    }
  } catch (const MalformedDatagram& error) {
    return IgnoreOnServerPort(datagram.from, error.what());
  }
  if (static_cast<int>(sessions_.size()) >= options_.max_clients && !ReclaimSilentSlot()) {
    return IgnoreOnServerPort(datagram.from, "an INIT: " + std::to_string(sessions_.size()) +
                                                 " clients already, the most served at once");
  }
  std::optional<UdpSocket> handler;
  try {
    handler.emplace(options_.bind_address, 0);
  } catch (const std::runtime_error& error) {  // out of sockets: refuse this client, keep serving the others
    return IgnoreOnServerPort(datagram.from, "an INIT: " + std::string(error.what()));
  }
  auto session = std::make_unique<Session>(next_session_id_++, std::move(*handler), datagram.from, Clock::now());
  session->socket.Connect(datagram.from);
  Send(*session, Reply(kInitAck).Byte(kMajorVersion).Byte(kMinorVersion));
  Log("client " + std::to_string(session->id) + " at " + datagram.from.ToString() + " connected (handler port " +
      std::to_string(session->socket.local().port) + ")");
  sessions_[session->id] = std::move(session);
  std::lock_guard lock(stats_mutex_);
  stats_.clients = static_cast<int>(sessions_.size());
}

// ---------------------------------------------------------------------------------------------------------
// A client's handler socket: every other command.

void OspServer::OnSessionDatagram(Session& session, const Datagram& datagram) {
  session.last_heard = Clock::now();
  session.spoke = true;
  if (datagram.truncated) return Ignore(&session, "a datagram longer than " + std::to_string(kMaxDatagramBytes) + " bytes");
  try {
    DatagramReader reader(datagram.bytes);
    Dispatch(session, reader.Byte(), reader);
  } catch (const MalformedDatagram& error) {
    Ignore(&session, error.what());
  }
}

void OspServer::Dispatch(Session& session, std::uint8_t command, DatagramReader& reader) {
  switch (command) {
    case kEnd: return OnEnd(session);
    case kResetCommunication: return OnResetCommunication(session);
    case kEventId: return OnEventId(session, reader);
    case kObserveEvent: return OnObserveEvent(session, reader);
    case kValueIds: return OnValueIds(session, reader);
    case kGetValue: return OnGetValue(session, reader);
    case kSetValue: return OnSetValue(session, reader);
    case kObserveValues: return OnObserveValues(session, reader, true);
    case kStopObservingValues: return OnObserveValues(session, reader, false);
    case kResetSimulation: return OnResetSimulation(session, reader);
    case kStep: return OnStep(session, reader);
    case kAgentOverview: return OnAgentOverview(session);
    case kAgentInfo: return OnAgentInfo(session, reader);
    case kTakeControl: return OnTakeControl(session, reader);
    case kReleaseControl: return OnReleaseControl(session, reader);
    case kValueIdAck:
    case kResetDoneAck:
    case kStepResultAck:
    case kAgentEntryAck:
    case kAgentValueAck:
    case kInit:  // a repeated INIT on the handler socket: already connected
      return;  // acknowledgements need no answer (the protocol does not require them to be checked)
    default: return Ignore(&session, "unknown command " + std::to_string(command));
  }
}

void OspServer::OnEnd(Session& session) {
  Send(session, Reply(kEndAck));
  DropSession(session.id, "ended the session");
}

void OspServer::OnResetCommunication(Session& session) {
  Send(session, Reply(kResetCommunicationAck));
  for (auto& [id, other] : sessions_) Send(*other, Reply(kResetSimulationAck));
  Log("client " + std::to_string(session.id) + " reset the communication: every client is dropped");
  sessions_.clear();
  std::lock_guard lock(stats_mutex_);
  stats_.clients = 0;
}

void OspServer::OnEventId(Session& session, DatagramReader& reader) {
  const int event = simulation_.events().Find(reader.String());
  Send(session, Reply(kEventIdReply).Int(event < 0 ? 0 : WireId(event)));
}

void OspServer::OnObserveEvent(Session& session, DatagramReader& reader) {
  const std::int32_t event_id = reader.Int();
  const bool known = event_id >= 1 && event_id <= simulation_.events().size();
  if (known) session.observed_events.insert(event_id - 1);
  Send(session, Reply(kObserveEventReply).Int(known ? event_id : 0));
}

void OspServer::OnValueIds(Session& session, DatagramReader& reader) {
  const std::string pattern = reader.String();
  std::vector<int> ids;
  try {
    ids = simulation_.repository().Match(pattern);
  } catch (const InputError& error) {  // an invalid or over-long expression matches nothing
    Ignore(&session, "command 40: " + std::string(error.what()));
  }
  Send(session, Reply(kValueIdsCount).Int(static_cast<std::int32_t>(ids.size())));
  for (std::size_t i = 0; i < ids.size(); ++i) {
    const std::string& path = simulation_.repository().path(ids[i]);
    Send(session, Reply(kValueIdEntry).Int(static_cast<std::int32_t>(i)).Int(WireId(ids[i])).String(path).String(path));
  }
}

void OspServer::OnGetValue(Session& session, DatagramReader& reader) {
  const std::int32_t value_id = reader.Int();
  if (value_id < 1 || value_id > simulation_.repository().size()) {
    return Send(session, Reply(kGetValueReply).Int(-1).String(""));
  }
  Send(session, Reply(kGetValueReply).Int(value_id).String(simulation_.repository().value(value_id - 1).ToString()));
}

void OspServer::OnSetValue(Session& session, DatagramReader& reader) {
  const std::int32_t value_id = reader.Int();
  const std::string text = reader.String();
  std::uint8_t status = 2;  // unknown id
  if (value_id >= 1 && value_id <= simulation_.repository().size()) {
    status = simulation_.repository().value(value_id - 1).SetFromString(text).empty() ? 1 : 0;
  }
  Send(session, Reply(kSetValueReply).Int(value_id).Byte(status));
}

void OspServer::OnObserveValues(Session& session, DatagramReader& reader, bool observe) {
  const std::int32_t count = reader.Count(4);
  DatagramWriter reply = Reply(observe ? kObserveValuesReply : kStopObservingValuesReply);
  reply.Int(count);
  for (std::int32_t i = 0; i < count; ++i) {
    const std::int32_t value_id = reader.Int();
    const bool known = value_id >= 1 && value_id <= simulation_.repository().size();
    if (known && observe) session.observed_values.insert(value_id - 1);
    if (known && !observe) session.observed_values.erase(value_id - 1);
    reply.Int(known ? value_id : 0);
  }
  Send(session, reply);
}

void OspServer::OnResetSimulation(Session& session, DatagramReader& reader) {
  session.reset_seed = reader.Int();
  if (!AnythingPending()) waiting_since_ = Clock::now();
  session.reset_requested = true;
  Send(session, Reply(kResetSimulationAck));
  ResetIfEveryoneAsked();
}

void OspServer::OnStep(Session& session, DatagramReader& reader) {
  const std::int32_t agent_id = reader.Int();
  const int agent = AgentIndexOf(agent_id);
  if (agent < 0 || !session.agents.contains(agent)) {
    return Ignore(&session, "a step for agent " + std::to_string(agent_id) + ", which it does not control");
  }
  const std::int32_t count = reader.Count(4);
  if (static_cast<std::size_t>(count) != agents_[agent].inputs.size()) {
    return Ignore(&session, "a step with " + std::to_string(count) + " inputs for agent " + std::to_string(agent_id) +
                                ", which has " + std::to_string(agents_[agent].inputs.size()));
  }
  std::vector<float> inputs(static_cast<std::size_t>(count));
  for (float& input : inputs) input = reader.Float();
  if (!AnythingPending()) waiting_since_ = Clock::now();
  session.step_inputs[agent] = std::move(inputs);
  Send(session, Reply(kStepAck).Int(agent_id));
  StepIfEveryoneIsReady();
}

void OspServer::OnAgentOverview(Session& session) {
  Send(session, Reply(kAgentCount).Int(static_cast<std::int32_t>(agents_.size())));
  for (std::size_t a = 0; a < agents_.size(); ++a) {
    const bool available = ControllerOf(static_cast<int>(a)) == 0;
    Send(session, Reply(kAgentEntry)
                      .Int(static_cast<std::int32_t>(a))
                      .Int(WireId(static_cast<int>(a)))
                      .String("Agent")
                      .Byte(available ? 1 : 0)
                      .String(agents_[a].name));
  }
}

void OspServer::OnAgentInfo(Session& session, DatagramReader& reader) {
  const std::int32_t agent_id = reader.Int();
  const int agent = AgentIndexOf(agent_id);
  if (agent < 0) return Send(session, Reply(kAgentInfoReply).Int(0).Int(0).Int(0).Int(0).String(""));
  const AgentInterface& interface = agents_[agent];
  Send(session, Reply(kAgentInfoReply)
                    .Int(agent_id)
                    .Int(static_cast<std::int32_t>(interface.inputs.size()))
                    .Int(static_cast<std::int32_t>(interface.outputs.size()))
                    .Int(0)
                    .String(interface.name));
  std::int32_t running_index = 0;
  for (const std::vector<InterfaceValue>* list : {&interface.inputs, &interface.outputs}) {
    for (const InterfaceValue& value : *list) {
      Send(session, Reply(kAgentValue)
                        .Int(running_index++)
                        .Float(static_cast<float>(value.range.norm_min))
                        .Float(static_cast<float>(value.range.norm_max))
                        .String(value.name));
    }
  }
}

void OspServer::OnTakeControl(Session& session, DatagramReader& reader) {
  const std::int32_t agent_id = reader.Int();
  const int agent = AgentIndexOf(agent_id);
  const int controller = agent < 0 ? -1 : ControllerOf(agent);
  const bool ok = agent >= 0 && (controller == 0 || controller == session.id);
  if (ok && controller == 0) {
    session.agents.insert(agent);
    Log("client " + std::to_string(session.id) + " controls agent " + agents_[agent].name);
  }
  Send(session, Reply(kTakeControlReply).Int(agent_id).Byte(ok ? 1 : 0));
}

void OspServer::OnReleaseControl(Session& session, DatagramReader& reader) {
  const std::int32_t agent_id = reader.Int();
  const int agent = AgentIndexOf(agent_id);
  std::uint8_t status = 0;  // failed: no such agent
  if (agent >= 0) status = session.agents.erase(agent) == 1 ? 1 : 2;
  if (status == 1) session.step_inputs.erase(agent);
  Send(session, Reply(kReleaseControlReply).Int(agent_id).Byte(status));
  StepIfEveryoneIsReady();
  ResetIfEveryoneAsked();
}

// ---------------------------------------------------------------------------------------------------------
// Synchronisation.

void OspServer::StepIfEveryoneIsReady() {
  bool any_controller = false;
  for (const auto& [id, session] : sessions_) {
    for (int agent : session->agents) {
      any_controller = true;
      if (!session->step_inputs.contains(agent)) return;
    }
  }
  if (!any_controller) return;
  RunStep();
  SendStepResults();
}

void OspServer::RunStep() {
  if (options_.before_step) options_.before_step(simulation_.time());
  for (auto& [id, session] : sessions_) {
    for (const auto& [agent, inputs] : session->step_inputs) {
      const std::vector<InterfaceValue>& values = agents_[agent].inputs;
      for (std::size_t i = 0; i < values.size(); ++i) {
        if (std::isfinite(inputs[i])) values[i].value->Set(values[i].range.ToRaw(inputs[i]));  // NaN: unchanged
      }
    }
  }
  try {
    if (simulation_.Step() != scene::SimulationStatus::kOk) Log("the simulation stopped: " + simulation_.message());
  } catch (const InputError& error) {  // a value a client wrote that the step refuses: the gateway serves on
    Log("the step did not run: " + std::string(error.what()));
  }
  if (options_.after_step) options_.after_step();
  std::lock_guard lock(stats_mutex_);
  ++stats_.steps;
}

void OspServer::SendStepResults() {
  const std::vector<int>& occurred = simulation_.events().occurred();
  const bool with_values = ProtocolSwitch(simulation_.repository(), kObservedValuesInStepReplyPath, true);
  for (auto& [id, session] : sessions_) {
    for (const auto& [agent, inputs] : session->step_inputs) {
      const std::vector<InterfaceValue>& outputs = agents_[agent].outputs;
      std::vector<std::int32_t> events;
      const std::size_t room = (kMaxDatagramBytes - 1 - kStepResultHeaderBytes - 4 * outputs.size()) / 4;
      for (int event : occurred) {
        if (session->observed_events.contains(event) && events.size() < room) events.push_back(WireId(event));
      }
      const std::size_t bytes_left = kMaxDatagramBytes - 1 - kStepResultHeaderBytes - 4 * (outputs.size() + events.size());
      const std::vector<ObservedValue> values = with_values ? ObservedValues(*session, bytes_left) : std::vector<ObservedValue>{};
      DatagramWriter reply = Reply(kStepResult);
      reply.Int(WireId(agent)).Int(static_cast<std::int32_t>(outputs.size())).Int(0);
      reply.Int(static_cast<std::int32_t>(events.size())).Int(static_cast<std::int32_t>(values.size()));
      for (const InterfaceValue& output : outputs) reply.Float(static_cast<float>(output.value->as_double()));
      for (std::int32_t event : events) reply.Int(event);
      for (const ObservedValue& value : values) reply.Int(value.id).String(value.text);
      Send(*session, reply);
    }
    session->step_inputs.clear();
  }
}

// The client's observed values in id order, as many as fit `room` bytes (each an int id and a NUL-terminated
// string). Those that do not fit are left out of this step's reply (the client reads them with 50); the first
// time, the log says so.
std::vector<OspServer::ObservedValue> OspServer::ObservedValues(Session& session, std::size_t room) {
  std::vector<ObservedValue> values;
  std::size_t used = 0;
  for (int id : session.observed_values) {
    std::string text = simulation_.repository().value(id).ToString();
    const std::size_t size = 4 + text.size() + 1;
    if (used + size > room) {
      if (!session.values_overflow_logged) {
        session.values_overflow_logged = true;
        Log("client " + std::to_string(session.id) + ": observes more values than a step reply carries; the first " +
            std::to_string(values.size()) + " of " + std::to_string(session.observed_values.size()) +
            " are sent, read the others with 50");
      }
      break;
    }
    used += size;
    values.push_back({WireId(id), std::move(text)});
  }
  return values;
}

void OspServer::ResetIfEveryoneAsked() {
  std::int32_t seed = 0;
  bool anyone_asked = false;
  for (const auto& [id, session] : sessions_) {
    if (session->reset_requested) {
      anyone_asked = true;
      seed = session->reset_seed;  // the last asker (by id) decides when several seeds differ
    } else if (!session->agents.empty()) {
      return;  // a controlling client has not asked yet
    }
  }
  if (!anyone_asked) return;
  try {
    simulation_.Reset(static_cast<std::uint32_t>(seed));
    if (options_.after_reset) options_.after_reset();
    Log("simulation reset with seed " + std::to_string(static_cast<std::uint32_t>(seed)));
  } catch (const InputError& error) {
    // A structure value written over OSP that cannot be built (crossed hinge stops): OSP has no error reply, so
    // the reset is answered, the world runs on as it was, and the log says why and what to fix.
    Log(std::string("reset refused, the world runs on unchanged: ") + error.what() + "; write a valid value and reset again");
  }
  for (auto& [id, session] : sessions_) {
    session->step_inputs.clear();
    if (!session->reset_requested) continue;
    session->reset_requested = false;
    Send(*session, Reply(kResetDone));
  }
  std::lock_guard lock(stats_mutex_);
  ++stats_.resets;
}

// ---------------------------------------------------------------------------------------------------------
// Housekeeping.

bool OspServer::BlocksOthers(const Session& session) const {
  if (session.agents.empty()) return false;
  bool step_pending = false;
  bool reset_pending = false;
  for (const auto& [id, other] : sessions_) {
    step_pending = step_pending || !other->step_inputs.empty();
    reset_pending = reset_pending || other->reset_requested;
  }
  if (reset_pending && !session.reset_requested) return true;
  if (!step_pending) return false;
  for (int agent : session.agents) {
    if (!session.step_inputs.contains(agent)) return true;
  }
  return false;
}

void OspServer::OnTick() {
  const Clock::time_point now = Clock::now();
  SummariseServerPort(now, false);
  std::vector<int> silent;
  std::vector<int> mute;  // never spoke after the INIT
  for (const auto& [id, session] : sessions_) {
    if (!session->spoke) {
      if (now - session->last_heard > options_.client_timeout) mute.push_back(id);
      continue;
    }
    const Clock::time_point silent_since = std::max(session->last_heard, waiting_since_);
    if (BlocksOthers(*session) && now - silent_since > options_.client_timeout) silent.push_back(id);
  }
  for (int id : silent) {
    DropSession(id, "was silent for more than " + std::to_string(options_.client_timeout.count()) + " ms");
    std::lock_guard lock(stats_mutex_);
    ++stats_.clients_timed_out;
  }
  if (!mute.empty()) {  // one line for a flood, not one per client
    Log(std::to_string(mute.size()) + " client(s) sent nothing to their handler port within " +
        std::to_string(options_.client_timeout.count()) + " ms of their INIT (first: client " +
        std::to_string(mute.front()) + "): dropped, their slots are free");
    for (int id : mute) ReclaimSession(id, "");
  }
}

bool OspServer::ReclaimSilentSlot() {
  const Clock::time_point now = Clock::now();
  int quietest = 0;
  Clock::time_point oldest = now - options_.client_timeout;
  for (const auto& [id, session] : sessions_) {
    if (session->last_heard < oldest) {
      oldest = session->last_heard;
      quietest = id;
    }
  }
  if (quietest == 0) return false;
  ReclaimSession(quietest, "was silent for " +
                               std::to_string(std::chrono::duration_cast<std::chrono::milliseconds>(now - oldest).count()) +
                               " ms while every slot was taken: its slot goes to a new client");
  return true;
}

void OspServer::ReclaimSession(int id, const std::string& why) {
  {
    std::lock_guard lock(stats_mutex_);
    ++stats_.clients_reclaimed;
  }
  DropSession(id, why);
}

void OspServer::DropSession(int id, const std::string& why) {
  const auto it = sessions_.find(id);
  if (it == sessions_.end()) return;
  if (!why.empty()) Log("client " + std::to_string(id) + " " + why + "; its agents are free");
  sessions_.erase(it);
  {
    std::lock_guard lock(stats_mutex_);
    stats_.clients = static_cast<int>(sessions_.size());
  }
  StepIfEveryoneIsReady();  // the others may have been waiting for it
  ResetIfEveryoneAsked();
}

void OspServer::Send(Session& session, const DatagramWriter& writer) {
  try {
    session.socket.Send(writer.Finish());
  } catch (const MalformedDatagram& error) {  // a reply too long for the protocol (an over-long value)
    Log("client " + std::to_string(session.id) + ": reply not sent: " + error.what());
  }
}

void OspServer::Ignore(Session* session, const std::string& why) {
  {
    std::lock_guard lock(stats_mutex_);
    ++stats_.datagrams_ignored;
  }
  if (session->warned) return;  // one line per client: a flood of garbage must not flood the log
  session->warned = true;
  Log("client " + std::to_string(session->id) + ": ignored " + why + " (further ignored datagrams not logged)");
}

// Anyone can send to the server port, from as many addresses as it likes: the first ignored datagram of each of the
// first kMaxLoggedSenders addresses is logged, everything else is counted and summed up in one line per
// server_log_summary_interval (docs/osp.md). 100,000 bad datagrams from one sender: two lines.
void OspServer::IgnoreOnServerPort(const Endpoint& from, const std::string& why) {
  {
    std::lock_guard lock(stats_mutex_);
    ++stats_.datagrams_ignored;
  }
  const std::pair<std::uint32_t, std::uint16_t> sender{from.address, from.port};
  if (!logged_senders_.contains(sender) && logged_senders_.size() < kMaxLoggedSenders) {
    logged_senders_.insert(sender);
    Log("ignored " + why + ", from " + from.ToString() + " (further ignored datagrams from it are counted, not logged)");
  } else {
    ++unlogged_ignored_;
    if (unlogged_senders_.size() <= kMaxLoggedSenders) unlogged_senders_.insert(sender);
  }
  SummariseServerPort(Clock::now(), false);
}

void OspServer::SummariseServerPort(Clock::time_point now, bool final) {
  if (unlogged_ignored_ == 0) {
    last_summary_ = now;
    return;
  }
  if (!final && now - last_summary_ < options_.server_log_summary_interval) return;
  const double seconds = std::chrono::duration<double>(now - last_summary_).count();
  const std::size_t senders = unlogged_senders_.size();
  char span[32];
  std::snprintf(span, sizeof span, "%.1f", seconds);
  Log("ignored " + std::to_string(unlogged_ignored_) + " more datagram(s) on the server port in the last " + span +
      " s, from " + (senders > kMaxLoggedSenders ? "more than " + std::to_string(kMaxLoggedSenders) : std::to_string(senders)) +
      " sender(s) (the first from each of the first " + std::to_string(kMaxLoggedSenders) + " senders is logged)");
  unlogged_ignored_ = 0;
  unlogged_senders_.clear();
  last_summary_ = now;
}

bool OspServer::AnythingPending() const {
  for (const auto& [id, session] : sessions_) {
    if (!session->step_inputs.empty() || session->reset_requested) return true;
  }
  return false;
}

int OspServer::ControllerOf(int agent) const {
  for (const auto& [id, session] : sessions_) {
    if (session->agents.contains(agent)) return id;
  }
  return 0;
}

int OspServer::AgentIndexOf(std::int32_t agent_id) const {
  return agent_id >= 1 && agent_id <= static_cast<std::int32_t>(agents_.size()) ? agent_id - 1 : -1;
}

}  // namespace orcs::osp
