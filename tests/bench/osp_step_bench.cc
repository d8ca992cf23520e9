// OSP step round trips per second for one client on loopback, the simulation step included, next to the bare
// simulation step rate of the same world (the default: one A-Series standing on the floor).
//
// BM_OspStepRoundTrip: an OspServer runs in its own thread on 127.0.0.1 (as in orcs-osp); the benchmark thread is
// the client, controlling the agent. One iteration is one synchronised step as an old client does it: send 80
// (42 normalised inputs), receive 81, receive 85 (37 outputs), send 86. BM_SimulationStep: Simulation::Step() in a
// loop. Both count wall-clock time (UseRealTime: the OSP work happens in the server thread), so items/s are steps
// per second either way. Every 1000 steps (10 s simulated) the simulation resets outside the timing.
//
//   osp_step_bench --benchmark_repetitions=5 --benchmark_min_time=2 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <cstdint>
#include <stdexcept>
#include <thread>
#include <vector>

#include "model/aseries/value_range.h"
#include "model/scene/simulation.h"
#include "worker/osp/osp_datagram.h"
#include "worker/osp/osp_protocol.h"
#include "worker/osp/osp_server.h"
#include "worker/osp/udp_socket.h"
#include "model/scene/world_setup.h"

namespace orcs::osp {
namespace {

constexpr int kEpisodeSteps = 1000;  // 10 s simulated, then reset
constexpr int kReplyTimeoutMs = 5000;

// The next datagram on `socket`, which must start with `code`; throws when none comes.
Datagram Expect(UdpSocket& socket, std::uint8_t code) {
  if (!socket.WaitReadable(kReplyTimeoutMs)) throw std::runtime_error("no reply " + std::to_string(code));
  std::optional<Datagram> datagram = socket.Receive();
  if (!datagram || datagram->bytes.empty() || datagram->bytes.front() != code) {
    throw std::runtime_error("expected reply " + std::to_string(code));
  }
  return *datagram;
}

void Send(UdpSocket& socket, const DatagramWriter& writer, const Endpoint& to) {
  socket.SendTo(writer.Finish(false), to);
}

// One client of a server running in its own thread.
class ClientOfServerThread {
 public:
  ClientOfServerThread() : client_("127.0.0.1", 0) {
    scene::SetUpWorld(simulation_, "", {}, {});
    simulation_.Reset(0);
    OspServerOptions options;
    options.port = 0;
    options.log = [](std::string_view) {};
    server_ = std::make_unique<OspServer>(simulation_, options);
    thread_ = std::thread([this] { server_->Run(); });
    Send(client_, DatagramWriter().Byte(kInit).Byte(kMajorVersion).Byte(kMinorVersion), server_->endpoint());
    handler_ = Expect(client_, kInitAck).from;
    Send(client_, DatagramWriter().Byte(kTakeControl).Int(1), handler_);
    Expect(client_, kTakeControlReply);
    step_.Byte(kStep).Int(1).Int(42);
    for (int motor = 0; motor < 21; ++motor) {
      step_.Float(0.0f);  // angle 0
      step_.Float(static_cast<float>(aseries::kDesiredTorqueRange.ToNormalised(aseries::kDefaultDesiredTorqueRaw)));
    }
  }
  ~ClientOfServerThread() {
    server_->Stop();
    thread_.join();
  }
  void Step() {
    Send(client_, step_, handler_);
    Expect(client_, kStepAck);
    Expect(client_, kStepResult);
    Send(client_, DatagramWriter().Byte(kStepResultAck), handler_);
  }
  void Reset() {
    Send(client_, DatagramWriter().Byte(kResetSimulation).Int(0), handler_);
    Expect(client_, kResetSimulationAck);
    Expect(client_, kResetDone);
    Send(client_, DatagramWriter().Byte(kResetDoneAck), handler_);
  }

 private:
  scene::Simulation simulation_;  // stepped only by the server thread
  std::unique_ptr<OspServer> server_;
  std::thread thread_;
  UdpSocket client_;
  Endpoint handler_;
  DatagramWriter step_;  // the step request, always the same inputs
};

void BM_OspStepRoundTrip(benchmark::State& state) {
  ClientOfServerThread client;
  int steps = 0;
  for (auto _ : state) {
    client.Step();
    if (++steps % kEpisodeSteps == 0) {
      state.PauseTiming();
      client.Reset();
      state.ResumeTiming();
    }
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_OspStepRoundTrip)->UseRealTime()->Unit(benchmark::kMicrosecond);

void BM_SimulationStep(benchmark::State& state) {
  scene::Simulation simulation;
  scene::SetUpWorld(simulation, "", {}, {});
  simulation.Reset(0);
  int steps = 0;
  for (auto _ : state) {
    simulation.Step();
    if (++steps % kEpisodeSteps == 0) {
      state.PauseTiming();
      simulation.Reset(0);
      state.ResumeTiming();
    }
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_SimulationStep)->UseRealTime()->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace orcs::osp

BENCHMARK_MAIN();
