// orcs-sim's pacing and ODCP: steps paced to the wall clock (--realtime) or delayed by the original's
// /Simulation/Delay, and ODCP 1.0 served for every agent between them (-port, docs/osp.md), so that a motion
// editor or slider tool moves the robots of a running orcs-sim directly.
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <ostream>
#include <string>
#include <vector>

#include "model/scene/simulation.h"
#include "worker/osp/odcp_server.h"

namespace orcs::sim {

class RealtimeRunner {
 public:
  /// `odcp_base_port` −1: no ODCP; otherwise one server per agent from that port (0 = ephemeral), numbered as in
  /// orcs-osp (skipping OSP's default port 45454), bound to `bind_address`. Throws InputError naming -port
  /// when a port cannot be bound.
  RealtimeRunner(scene::Simulation& simulation, int odcp_base_port, const std::string& bind_address);

  /// "orcs-sim odcp AGENT=ADDRESS:PORT", one line per ODCP server.
  void PrintEndpoints(std::ostream& out) const;
  /// Waits until step `index` is due — `index` step durations after the first call — answering ODCP datagrams
  /// meanwhile. A step that is late already is not waited for (the run catches up, it skips nothing).
  void WaitForStep(std::int64_t index, double step_seconds);
  /// Waits `seconds` (≤ 0: not at all), answering ODCP datagrams meanwhile and those already waiting.
  void Pause(double seconds);

 private:
  using Clock = std::chrono::steady_clock;
  // Answers datagrams until `deadline`, and at least once those already waiting.
  void ServeUntil(Clock::time_point deadline);

  std::vector<std::unique_ptr<osp::AgentMotors>> motors_;  // what each server drives (outlives it)
  std::vector<std::unique_ptr<osp::OdcpServer>> servers_;  // by agent index
  Clock::time_point start_;                                // when step 0 was due
  bool started_ = false;                                   // WaitForStep has been called
};

}  // namespace orcs::sim
