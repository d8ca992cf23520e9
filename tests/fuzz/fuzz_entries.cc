#include "tests/fuzz/fuzz_entries.h"

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <google/protobuf/stubs/logging.h>
#include <nlohmann/json.hpp>

#include "clients/gap/measured_run.h"
#include "model/control/keyframe_player.h"
#include "model/control/keyframe_record.h"
#include "model/core/error.h"
#include "model/core/json_node.h"
#include "model/core/value_file.h"
#include "model/scene/environment_reader.h"
#include "model/scene/scenario.h"
#include "model/scene/simulation.h"
#include "model/scene/world_model.h"
#include "orcs/v1/broker.pb.h"
#include "proto/envelope.h"
#include "worker/evaluation/evaluation.h"
#include "worker/job/job_translation.h"
#include "worker/job/result_json.h"
#include "worker/osp/keyframe_sniffer.h"
#include "worker/osp/odcp_server.h"
#include "worker/osp/osp_protocol.h"
#include "worker/osp/osp_server.h"

namespace orcs::fuzz {
namespace {

// The world the value, motion and OSP entries work on: an A-Series and a box on the floor.
constexpr const char* kASeriesWorld = R"xml(<ORCS version="1.0">
  <Environment>
    <object type="box" name="Box" position="(0.4, 0.1, 0.4)" dimension="(0.2, 0.2, 0.2)" dynamic="true" mass="0.1"/>
  </Environment>
  <Agent><ASeries name="Humanoid"/></Agent>
</ORCS>)xml";

// Compiled once; every input gets a fresh simulation on it, so no input sees what an earlier one changed.
std::shared_ptr<const scene::WorldModel> ASeriesModel() {
  static const std::shared_ptr<const scene::WorldModel> model = [] {
    const scene::EnvironmentDescription environment = scene::EnvironmentReader::ReadString(kASeriesWorld, "fuzz");
    scene::Simulation registry;
    registry.LoadEnvironment(environment);
    return scene::WorldModel::Compile(environment, registry.repository());
  }();
  return model;
}

std::unique_ptr<scene::Simulation> FreshASeries() {
  auto simulation = std::make_unique<scene::Simulation>();
  simulation->Attach(ASeriesModel());
  simulation->Reset(0);
  return simulation;
}

FeedResult Rejected(const std::exception& error) { return {false, error.what()}; }

// Runs `feed`, turning the documented errors into a rejection; anything else propagates to the fuzzer.
template <typename Feed>
FeedResult Guarded(Feed feed) {
  try {
    feed();
    return {};
  } catch (const InputError& error) {
    return Rejected(error);
  } catch (const PhysicsError& error) {
    return Rejected(error);
  }
}

// A check the fuzzer must see fail: aborts with the reason (a sanitizer-style report, not a rejection).
void Require(bool condition, const char* what) {
  if (condition) return;
  std::fprintf(stderr, "fuzz invariant broken: %s\n", what);
  std::abort();
}

// A private temporary folder per process, removed at exit; value files are read by name, so each input is written
// to a file in it.
class ScratchFolder {
 public:
  ScratchFolder()
      : dir_(std::filesystem::temp_directory_path() / ("orcs-fuzz-" + std::to_string(static_cast<long>(getpid())))) {
    std::filesystem::create_directories(dir_);
  }
  ~ScratchFolder() {
    std::error_code ignored;
    std::filesystem::remove_all(dir_, ignored);
  }
  std::filesystem::path file() const { return dir_ / "input.val"; }

 private:
  std::filesystem::path dir_;
};

std::filesystem::path ScratchFile() {
  static const ScratchFolder folder;
  return folder.file();
}

void RequireSameRows(const control::KeyframeRecord& a, const control::KeyframeRecord& b) {
  Require(a.frames.size() == b.frames.size(), "a written record reads back with another row count");
  for (std::size_t i = 0; i < a.frames.size(); ++i) {
    Require(a.frames[i].time_ms == b.frames[i].time_ms, "a written record reads back with another time");
    Require(a.frames[i].inputs == b.frames[i].inputs, "a written record reads back with other inputs");
  }
}

void PlayMotion(std::string_view text, int motor_count) {
  const control::KeyframeRecord record = control::ParseKeyframeRecord(text, "fuzz.csv", motor_count);
  RequireSameRows(record, control::ParseKeyframeRecord(control::FormatKeyframeRecord(record, {"fuzz"}), "round trip",
                                                       motor_count));
  if (motor_count != 21) return;
  const std::unique_ptr<scene::Simulation> simulation = FreshASeries();
  control::KeyframePlayer player(record, "Humanoid", simulation->agent(0).motor_names(), simulation->repository());
  player.Apply(0.0);
  player.Apply(player.duration() / 2);
  player.Apply(player.duration());
}

// What orcs-worker does with a job it cannot run: a result with the error, which must reach the broker, so it must
// parse there (a message that does not is dropped, and the job would never finish).
void RequireDeliverable(const v1::Job& job, const InputError& error) {
  evaluation::EvaluationOutcome outcome;
  outcome.status = evaluation::EvaluationStatus::kInvalidInput;
  outcome.message = error.what();
  v1::WorkerToBroker answer;
  answer.set_protocol_version(proto::kProtocolVersion);
  *answer.mutable_result() = worker::ToResult(job, outcome);
  answer.mutable_result()->set_protocol_version(proto::kProtocolVersion);
  const std::string bytes = answer.SerializeAsString();
  v1::WorkerToBroker received;
  if (proto::ParseEnvelope(bytes.data(), bytes.size(), received) != proto::EnvelopeCheck::kOk) {
    std::fprintf(stderr, "undeliverable result message: %s\n", error.what());
    Require(false, "the result of a rejected job does not parse at the broker");
  }
}

void CheckJob(const v1::Job& job) {
  try {
    evaluation::CheckRequest(worker::RequestOf(job));
  } catch (const InputError& error) {
    RequireDeliverable(job, error);
    throw;
  }
}

// The results.jsonl line of a result, as the client writes it.
void WriteResult(const v1::Result& result) { [[maybe_unused]] const std::string line = worker::ResultToJson(result).dump(); }

// Where the OSP server's replies go: a socket of ours that nobody reads (the kernel drops what overflows).
osp::Endpoint ReplySink() {
  static osp::UdpSocket sink("127.0.0.1", 0);
  return sink.local();
}

osp::Datagram DatagramOf(std::string bytes) {
  osp::Datagram datagram;
  datagram.bytes.assign(bytes.begin(), bytes.end());
  datagram.from = ReplySink();
  return datagram;
}

}  // namespace

std::vector<std::string> SplitDatagrams(std::string_view data) {
  std::vector<std::string> datagrams;
  while (data.size() >= 2) {
    const std::size_t length = static_cast<unsigned char>(data[0]) | (static_cast<std::size_t>(static_cast<unsigned char>(data[1])) << 8);
    data.remove_prefix(2);
    const std::size_t take = std::min(length, data.size());
    datagrams.emplace_back(data.substr(0, take));
    data.remove_prefix(take);
  }
  return datagrams;
}

std::string JoinDatagrams(const std::vector<std::string>& datagrams) {
  std::string data;
  for (const std::string& datagram : datagrams) {
    data += static_cast<char>(datagram.size() & 0xff);
    data += static_cast<char>((datagram.size() >> 8) & 0xff);
    data += datagram;
  }
  return data;
}

FeedResult FeedEnvironmentXml(std::string_view data) {
  return Guarded([&] {
    scene::Simulation simulation;
    simulation.LoadEnvironment(scene::EnvironmentReader::ReadString(std::string(data), "fuzz.xml"));
    simulation.Build();
    simulation.Reset(0);
    simulation.Step();
    simulation.Step();
  });
}

FeedResult FeedValueFile(std::string_view data) {
  return Guarded([&] {
    {
      std::ofstream out(ScratchFile(), std::ios::binary | std::ios::trunc);
      out.write(data.data(), static_cast<std::streamsize>(data.size()));
    }
    const std::unique_ptr<scene::Simulation> simulation = FreshASeries();
    ValueFile::Apply(ScratchFile().string(), simulation->repository());
    simulation->StepDuration();
  });
}

FeedResult FeedMotionRecord(std::string_view data) {
  // Both motor counts are tried; the input is accepted when either reads it.
  const FeedResult aseries = Guarded([&] { PlayMotion(data, 21); });
  const FeedResult pendulum = Guarded([&] { PlayMotion(data, 1); });
  return aseries.accepted ? aseries : pendulum.accepted ? pendulum : aseries;
}

FeedResult FeedScenarioJson(std::string_view data) {
  return Guarded([&] {
    evaluation::EvaluationRequest request;
    request.scenario = scene::ParseScenario(ParseJson(std::string(data), "fuzz.json"), "fuzz.json");
    if (!request.scenario.genome.is_null()) request.genome = request.scenario.genome;  // as orcs-batch does
    evaluation::CheckRequest(request);
  });
}

FeedResult FeedBrokerMessage(std::string_view data) {
  static const bool quiet = [] {  // protobuf logs every invalid UTF-8 string; the parse result says it all
    google::protobuf::SetLogHandler(nullptr);
    return true;
  }();
  (void)quiet;
  if (data.empty()) return {false, "no receiver byte"};
  const int receiver = static_cast<unsigned char>(data[0]) % 4;
  data.remove_prefix(1);
  return Guarded([&] {
    proto::EnvelopeCheck check = proto::EnvelopeCheck::kOk;
    if (receiver == 0) {  // the broker's worker port
      v1::WorkerToBroker message;
      check = proto::ParseEnvelope(data.data(), data.size(), message);
      if (check == proto::EnvelopeCheck::kOk && message.has_result()) WriteResult(message.result());
    } else if (receiver == 1) {  // the broker's client port
      v1::ClientToBroker message;
      check = proto::ParseEnvelope(data.data(), data.size(), message);
    } else if (receiver == 2) {  // a worker
      v1::BrokerToWorker message;
      check = proto::ParseEnvelope(data.data(), data.size(), message);
      if (check == proto::EnvelopeCheck::kOk && message.has_job()) CheckJob(message.job());
    } else {  // a client
      v1::BrokerToClient message;
      check = proto::ParseEnvelope(data.data(), data.size(), message);
      if (check == proto::EnvelopeCheck::kOk && message.has_result()) WriteResult(message.result());
    }
    if (check != proto::EnvelopeCheck::kOk) throw InputError("fuzz message", 0, std::string(proto::Describe(check)));
  });
}

FeedResult FeedOspDatagrams(std::string_view data) {
  const std::unique_ptr<scene::Simulation> simulation = FreshASeries();
  osp::OspServerOptions options;
  options.port = 0;
  options.log = [](std::string_view) {};
  osp::OspServer server(*simulation, options);
  server.Deliver(0, DatagramOf({static_cast<char>(osp::kInit), static_cast<char>(osp::kMajorVersion),
                                static_cast<char>(osp::kMinorVersion)}));
  for (std::string datagram : SplitDatagrams(data)) {
    if (datagram.empty()) continue;
    const int socket = static_cast<unsigned char>(datagram[0]);
    server.Deliver(socket, DatagramOf(datagram.substr(1)));
  }
  const std::uint64_t ignored = server.stats().datagrams_ignored;
  if (ignored == 0) return {};
  return {false, std::to_string(ignored) + " datagrams ignored"};
}

FeedResult FeedOdcpDatagrams(std::string_view data) {
  auto now = std::chrono::steady_clock::time_point{};
  osp::KeyframeSniffer sniffer(21, [&now] { return now += std::chrono::milliseconds(20); });
  osp::OdcpServerOptions options;
  options.port = 0;
  options.log = [](std::string_view) {};
  osp::OdcpServer server(sniffer, options);
  for (const std::string& datagram : SplitDatagrams(data)) server.OnDatagram(DatagramOf(datagram));
  if (!sniffer.record().frames.empty()) {
    const std::string text = control::FormatKeyframeRecord(sniffer.record(), {"fuzz"});
    try {
      RequireSameRows(sniffer.record(), control::ParseKeyframeRecord(text, "sniffed", 21));
    } catch (const InputError& error) {
      std::fprintf(stderr, "%s\n", error.what());
      Require(false, "a sniffed record does not read back");
    }
  }
  if (server.stats().datagrams_ignored == 0) return {};
  return {false, std::to_string(server.stats().datagrams_ignored) + " datagrams ignored"};
}

FeedResult FeedMeasuredRun(std::string_view data) {
  return Guarded([&] {
    std::optional<gap::ColumnMapping> mapping;
    std::string_view csv = data;
    if (const std::size_t split = data.find("\n---\n"); split != std::string_view::npos) {
      mapping = gap::ParseColumnMapping(ParseJson(std::string(data.substr(0, split)), "fuzz.json"), "fuzz.json");
      csv = data.substr(split + 5);
    }
    const gap::MeasuredRun run = gap::ParseMeasuredRun(csv, "fuzz.csv", mapping ? &*mapping : nullptr);
    gap::CommandsAsRecord(run, run.commanded);
  });
}

const std::vector<FuzzTarget>& FuzzTargets() {
  static const std::vector<FuzzTarget> targets = {
      {"environment_xml", FeedEnvironmentXml}, {"value_file", FeedValueFile},
      {"motion_record", FeedMotionRecord},     {"scenario_json", FeedScenarioJson},
      {"broker_message", FeedBrokerMessage},   {"osp_datagram", FeedOspDatagrams},
      {"odcp_datagram", FeedOdcpDatagrams},    {"measured_run", FeedMeasuredRun},
  };
  return targets;
}

}  // namespace orcs::fuzz
