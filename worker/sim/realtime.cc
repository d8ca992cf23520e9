#include "worker/sim/realtime.h"

#include <poll.h>

#include <algorithm>
#include <cmath>

#include "model/core/error.h"
#include "worker/osp/protocol_values.h"

namespace orcs::sim {
namespace {

// OSP's default port: orcs-sim numbers its ODCP ports as orcs-osp does, so an agent has the same port in both.
constexpr int kOspDefaultPort = 45454;

}  // namespace

RealtimeRunner::RealtimeRunner(scene::Simulation& simulation, int odcp_base_port, const std::string& bind_address) {
  if (odcp_base_port < 0) return;
  try {
    const std::vector<std::uint16_t> ports = osp::OdcpPorts(odcp_base_port, simulation.agent_count(), kOspDefaultPort);
    for (int a = 0; a < simulation.agent_count(); ++a) {
      motors_.push_back(std::make_unique<osp::AgentMotors>(
          osp::MakeAgentInterface(simulation, a), simulation.repository().Find(osp::kOdcpReportGoalAnglesPath)));
      osp::OdcpServerOptions options;
      options.bind_address = bind_address;
      options.port = ports[static_cast<std::size_t>(a)];
      options.name = "orcs-sim: ODCP " + motors_.back()->name();
      servers_.push_back(std::make_unique<osp::OdcpServer>(*motors_.back(), options));
    }
  } catch (const std::runtime_error& error) {  // a port in use, an address that cannot be bound
    throw InputError(std::string("-port: ") + error.what());
  }
}

void RealtimeRunner::PrintEndpoints(std::ostream& out) const {
  for (std::size_t a = 0; a < servers_.size(); ++a) {
    out << "orcs-sim odcp " << motors_[a]->name() << "=" << servers_[a]->endpoint().ToString() << std::endl;
  }
}

void RealtimeRunner::WaitForStep(std::int64_t index, double step_seconds) {
  if (!started_) {
    start_ = Clock::now();
    started_ = true;
  }
  const auto offset = std::chrono::duration<double>(static_cast<double>(index) * step_seconds);
  ServeUntil(start_ + std::chrono::duration_cast<Clock::duration>(offset));
}

void RealtimeRunner::Pause(double seconds) {
  const auto wait = std::chrono::duration<double>(std::max(0.0, seconds));
  ServeUntil(Clock::now() + std::chrono::duration_cast<Clock::duration>(wait));
}

void RealtimeRunner::ServeUntil(Clock::time_point deadline) {
  std::vector<pollfd> fds;
  for (const auto& server : servers_) fds.push_back({server->fd(), POLLIN, 0});
  // Bounded by the deadline: every pass either serves a datagram or waits until the deadline. The first pass
  // runs even when the deadline has passed, so that what is waiting is answered between any two steps.
  bool first = true;
  for (Clock::time_point now = Clock::now(); first || now < deadline; now = Clock::now(), first = false) {
    const auto left = std::chrono::duration_cast<std::chrono::nanoseconds>(std::max(deadline - now, Clock::duration{}));
    const timespec timeout{static_cast<time_t>(left.count() / 1000000000),
                           static_cast<long>(left.count() % 1000000000)};
    for (pollfd& entry : fds) entry.revents = 0;
    if (ppoll(fds.data(), fds.size(), &timeout, nullptr) <= 0) continue;
    for (std::size_t s = 0; s < fds.size(); ++s) {
      if (fds[s].revents & POLLIN) servers_[s]->OnReadable();
    }
  }
}

}  // namespace orcs::sim
