#include "tests/fuzz/fuzz_seeds.h"

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <type_traits>

#include "model/core/error.h"
#include "model/core/value_file.h"
#include "model/scene/environment_reader.h"
#include "model/scene/scenario.h"
#include "model/scene/simulation.h"
#include "orcs/v1/broker.pb.h"
#include "proto/envelope.h"
#include "tests/fuzz/fuzz_entries.h"
#include "worker/osp/odcp_server.h"
#include "worker/osp/osp_datagram.h"
#include "worker/osp/osp_protocol.h"

namespace orcs::fuzz {
namespace {

namespace fs = std::filesystem;

std::string ReadText(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file.string(), 0, "cannot read the file");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// The files in `dir` whose names end in `extension`, sorted, as seeds named after them.
std::vector<Seed> FilesIn(const fs::path& dir, const std::string& extension) {
  std::vector<fs::path> files;
  for (const fs::directory_entry& entry : fs::directory_iterator(dir)) {
    if (entry.is_regular_file() && entry.path().extension() == extension) files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  std::vector<Seed> seeds;
  for (const fs::path& file : files) seeds.push_back({file.filename().string(), ReadText(file)});
  return seeds;
}

// The shipped environments as a job carries them: their robot files inline (EnvironmentReader::InlineRobotFiles).
std::vector<Seed> InlinedEnvironments(const fs::path& root) {
  const fs::path dir = root / "scenarios/environments";
  std::vector<Seed> seeds = FilesIn(dir, ".xml");
  for (Seed& seed : seeds) seed.bytes = scene::EnvironmentReader::InlineRobotFiles(seed.bytes, (dir / seed.name).string());
  return seeds;
}

std::vector<Seed> ResolvedScenarios(const fs::path& root) {
  std::vector<Seed> seeds;
  for (Seed& seed : FilesIn(root / "scenarios/examples", ".json")) {
    seeds.push_back({seed.name, scene::ResolveScenarioFile((root / "scenarios/examples" / seed.name).string()).dump(1)});
  }
  return seeds;
}

// Value files as ValueFile::Save writes them, from an A-Series world, plus a hand-written one with comments.
std::vector<Seed> ValueFiles() {
  scene::Simulation simulation;
  simulation.LoadEnvironment(scene::EnvironmentReader::ReadString(
      R"(<ORCS version="1.0"><Agent><ASeries name="Humanoid"/></Agent></ORCS>)", "seed"));
  simulation.Build();
  const fs::path file = fs::temp_directory_path() / ("orcs-fuzz-seed-" + std::to_string(getpid()) + ".val");
  std::vector<Seed> seeds;
  const std::vector<std::pair<std::string, std::string>> selections = {
      {"simulation.val", "/Simulation/.*"}, {"knees.val", "/Sim/Humanoid/.*/Knee/.*"}, {"floor.val", ".*Floor.*"}};
  for (const auto& [name, expression] : selections) {
    ValueFile::Save(file.string(), simulation.repository(), "2026-01-01 00:00:00", expression);
    seeds.push_back({name, ReadText(file)});
  }
  fs::remove(file);
  seeds.push_back({"hand_written.val",
                   "#ORCS Values\n# a comment\n  /Simulation/TimeStepSize = 0.01  \n\n"
                   "/Sim/Humanoid/Right/Knee/DesiredAngle=-12.5\n/Sim/Humanoid/Right/Knee/DesiredTorque=1\n"});
  return seeds;
}

// The receiver byte FeedBrokerMessage reads first, then the envelope.
template <typename Envelope>
std::string Serialised(Envelope envelope) {
  envelope.set_protocol_version(proto::kProtocolVersion);
  char receiver = 0;
  if constexpr (std::is_same_v<Envelope, v1::ClientToBroker>) receiver = 1;
  if constexpr (std::is_same_v<Envelope, v1::BrokerToWorker>) receiver = 2;
  if constexpr (std::is_same_v<Envelope, v1::BrokerToClient>) receiver = 3;
  return std::string(1, receiver) + envelope.SerializeAsString();
}

v1::Job ExampleJob(const fs::path& root, const std::string& scenario) {
  v1::Job job;
  job.set_protocol_version(proto::kProtocolVersion);
  job.set_job_id("job-1");
  job.set_batch_id("batch-1");
  job.set_scenario_json(scene::ResolveScenarioFile((root / "scenarios/examples" / scenario).string()).dump());
  job.set_seed(42);
  v1::Override* override = job.add_overrides();
  override->set_path("/Simulation/ODE/FrictionScaling");
  override->set_value("0.9");
  job.set_time_limit_seconds(60);
  return job;
}

v1::Result ExampleResult() {
  v1::Result result;
  result.set_protocol_version(proto::kProtocolVersion);
  result.set_job_id("job-1");
  result.set_batch_id("batch-1");
  result.set_status(v1::Result::OK);
  result.set_fitness(-0.25);
  v1::Result::ParameterSetResult* set = result.add_parameter_sets();
  set->set_index(0);
  v1::DrawnValue* drawn = set->add_drawn();
  drawn->set_path("/Simulation/ODE/FrictionScaling");
  drawn->set_value(0.93);
  v1::Term* term = set->add_terms();
  term->set_name("tracking_error");
  term->set_value(0.25);
  set->set_fitness(-0.25);
  set->set_status(v1::Result::OK);
  v1::LogFile* log = result.add_logs();
  log->set_name("set-0.csv");
  log->set_csv("# columns: time,/Sim/Pendulum/Motor/JointAngle\n0,0\n0.01,0.5\n");
  result.set_worker_id("host-1234");
  result.mutable_timings()->set_run_seconds(0.5);
  result.mutable_timings()->set_simulated_seconds(2);
  result.set_attempts(1);
  return result;
}

std::vector<Seed> BrokerMessages(const fs::path& root) {
  std::vector<Seed> seeds;
  v1::WorkerToBroker ready;
  ready.mutable_ready()->set_worker_id("host-1234");
  ready.mutable_ready()->set_credit(2);
  seeds.push_back({"worker_ready.pb", Serialised(ready)});
  v1::WorkerToBroker result;
  *result.mutable_result() = ExampleResult();
  seeds.push_back({"worker_result.pb", Serialised(result)});
  v1::WorkerToBroker worker_heartbeat;
  worker_heartbeat.mutable_heartbeat();
  seeds.push_back({"worker_heartbeat.pb", Serialised(worker_heartbeat)});
  v1::WorkerToBroker worker_disconnect;
  worker_disconnect.mutable_disconnect()->set_reason("shutting down");
  seeds.push_back({"worker_disconnect.pb", Serialised(worker_disconnect)});

  v1::ClientToBroker submit;
  submit.mutable_submit()->set_batch_id("batch-1");
  submit.mutable_submit()->set_client_id("client-1");
  *submit.mutable_submit()->add_jobs() = ExampleJob(root, "pendulum_keyframes.json");
  seeds.push_back({"client_submit.pb", Serialised(submit)});
  v1::ClientToBroker cancel;
  cancel.mutable_cancel()->set_batch_id("batch-1");
  seeds.push_back({"client_cancel.pb", Serialised(cancel)});

  v1::BrokerToWorker job;
  *job.mutable_job() = ExampleJob(root, "pendulum_keyframes.json");
  seeds.push_back({"broker_job_keyframes.pb", Serialised(job)});
  v1::BrokerToWorker oscillator;
  *oscillator.mutable_job() = ExampleJob(root, "swing_oscillator.json");
  oscillator.mutable_job()->set_genome_json("[30, 2, 0, 0, 30, 2, 3, 0]");
  seeds.push_back({"broker_job_oscillator.pb", Serialised(oscillator)});

  v1::BrokerToClient accepted;
  accepted.mutable_accepted()->set_batch_id("batch-1");
  accepted.mutable_accepted()->set_job_count(1);
  accepted.mutable_accepted()->set_queued(1);
  seeds.push_back({"client_accepted.pb", Serialised(accepted)});
  v1::BrokerToClient to_client;
  *to_client.mutable_result() = ExampleResult();
  seeds.push_back({"client_result.pb", Serialised(to_client)});
  v1::BrokerToClient error;
  error.mutable_error()->set_batch_id("batch-1");
  error.mutable_error()->set_message("job 0: empty job_id");
  seeds.push_back({"client_error.pb", Serialised(error)});
  return seeds;
}

std::string Bytes(const osp::DatagramWriter& writer) {
  const std::vector<std::uint8_t> bytes = writer.Finish(false);
  return std::string(bytes.begin(), bytes.end());
}

// A datagram to client 1's handler socket (see FeedOspDatagrams).
std::string ToClient(const osp::DatagramWriter& writer) { return std::string(1, '\x01') + Bytes(writer); }

osp::DatagramWriter Command(std::uint8_t command) {
  osp::DatagramWriter writer;
  writer.Byte(command);
  return writer;
}

// An old client's session: overview, agent info, take control, observe values and an event, two steps, a reset.
std::vector<Seed> OspSessions() {
  osp::DatagramWriter step = Command(osp::kStep);
  step.Int(1).Int(42);
  for (int i = 0; i < 42; ++i) step.Float(i % 2 == 0 ? 0.1f : 0.5f);
  osp::DatagramWriter observe = Command(osp::kObserveValues);
  observe.Int(2).Int(1).Int(5);
  const std::vector<std::string> controlled = {
      ToClient(Command(osp::kAgentOverview)),  ToClient(Command(osp::kAgentInfo).Int(1)),
      ToClient(Command(osp::kTakeControl).Int(1)), ToClient(observe),
      ToClient(Command(osp::kEventId).String("/Simulation/Step")), ToClient(Command(osp::kObserveEvent).Int(1)),
      ToClient(step), ToClient(Command(osp::kStepResultAck)), ToClient(step),
      ToClient(Command(osp::kResetSimulation).Int(7)), ToClient(Command(osp::kReleaseControl).Int(1)),
      ToClient(Command(osp::kEnd))};
  const std::vector<std::string> values = {
      ToClient(Command(osp::kValueIds).String("/Simulation/.*")), ToClient(Command(osp::kGetValue).Int(3)),
      ToClient(Command(osp::kSetValue).Int(3).String("0.5")), ToClient(Command(osp::kStopObservingValues).Int(1).Int(3)),
      ToClient(Command(osp::kResetCommunication))};
  osp::DatagramWriter init = Command(osp::kInit);
  init.Byte(osp::kMajorVersion).Byte(osp::kMinorVersion);
  const std::vector<std::string> two_clients = {
      std::string(1, '\0') + Bytes(init), ToClient(Command(osp::kTakeControl).Int(1)),
      std::string(1, '\x02') + Bytes(Command(osp::kAgentOverview)), ToClient(step),
      std::string(1, '\x02') + Bytes(Command(osp::kTakeControl).Int(1)), ToClient(Command(osp::kEnd))};
  return {{"control_session.bin", JoinDatagrams(controlled)},
          {"value_session.bin", JoinDatagrams(values)},
          {"two_clients.bin", JoinDatagrams(two_clients)}};
}

// A motion editor's session: connect, two set-motors, get-motors, disconnect.
std::vector<Seed> OdcpSessions() {
  osp::DatagramWriter set_motors = Command(osp::kOdcpSetMotors);
  for (int i = 0; i < 21; ++i) set_motors.Int(512 + 10 * i);
  for (int i = 0; i < 21; ++i) set_motors.Int(1023);
  osp::DatagramWriter centre = Command(osp::kOdcpSetMotors);
  for (int i = 0; i < 42; ++i) centre.Int(512);
  return {{"editor_session.bin",
           JoinDatagrams({Bytes(Command(osp::kOdcpConnect)), Bytes(set_motors), Bytes(Command(osp::kOdcpGetMotors)),
                          Bytes(centre), Bytes(Command(osp::kOdcpDisconnect))})},
          {"probe.bin", JoinDatagrams({Bytes(Command(osp::kOdcpConnect)), Bytes(Command(osp::kOdcpGetMotors)),
                                       Bytes(Command(osp::kOdcpDisconnect))})}};
}

// An orcs-sim log of the pendulum rig and a robot logger's CSV with its column mapping (docs/gap_measured_data.md).
std::vector<Seed> MeasuredRuns() {
  return {{"pendulum_log.csv",
           "# orcs-sim log\n# environment: scenarios/environments/pendulum.xml\n# seed: 0\n"
           "# columns: time,/Sim/Pendulum/Motor/DesiredAngle,/Sim/Pendulum/Motor/DesiredTorque,"
           "/Sim/Pendulum/Motor/JointAngle\n"
           "0,0,0.586810005,0\n0.01,0,1,-0.0501782495117635\n0.02,0,1,0.19046842437259234\n"
           "0.03,0,1,-0.2494817702416845\n"},
          {"mapped_logger.txt",
           R"({"agent": "Humanoid", "delimiter": ";", "time": {"column": "t_ms", "scale": 0.001},
 "channels": [{"motor": "Right/Knee", "desired_angle": {"column": "cmd_knee"}, "desired_torque": {"constant": 1},
   "joint_angle": {"column": "pos_knee", "scale": 0.29296875, "offset": -150}},
  {"motor": "Right/Hip", "joint_angle": {"column": "pos_hip"}}]})"
           "\n---\n"
           "# exported by the robot's logger\n\"t_ms\"; cmd_knee ; pos_knee;pos_hip\n0;10;512;60\n20;20;522;61\n"
           "40;30;532;62\n"}};
}

// One connection per seed: '0' + requests to files mode, '1' + requests to live mode ("@token@" = the control
// token). Each route of docs/viewer-api.md once, every answer 2xx.
std::string Get(const std::string& target) { return "GET " + target + " HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n"; }

std::string Post(const std::string& target, const std::string& body, bool controlled) {
  return "POST " + target + " HTTP/1.1\r\nHost: 127.0.0.1\r\n" + (controlled ? "X-Orcs-Token: @token@\r\n" : "") +
         "Content-Type: application/json\r\nContent-Length: " + std::to_string(body.size()) + "\r\n\r\n" + body;
}

std::vector<Seed> ViewRequests() {
  return {{"files_page.http", "0" + Get("/") + Get("/assets/app.js") + Get("/api/session")},
          {"files_recording.http", "0" + Get("/api/recording/r0") + Get("/api/recording/r0/times") +
                                       Get("/api/recording/r0/channels?ids=0,3,5") +
                                       Get("/api/recording/r0/contacts")},
          {"files_compressed.http",
           "0GET /api/session HTTP/1.1\r\nHost: 127.0.0.1\r\nAccept-Encoding: br\r\n\r\n"
           "GET /api/batch/b0 HTTP/1.1\r\nHost: 127.0.0.1\r\nAccept-Encoding: gzip, deflate\r\n\r\n"},
          {"files_batch.http", "0" + Get("/api/batch/b0") + Get("/api/recording/r1/channels?ids=1")},
          {"live_watch.http", "1" + Get("/api/session") + Get("/api/live/world") + Get("/api/live/frame?since=-1") +
                                  Get("/api/live/values?filter=.*Knee.*") + Get("/api/live/files")},
          {"live_control.http",
           "1" + Post("/api/live/control", R"({"action":"step","realtime":false})", true) +
               Post("/api/live/values", R"({"path":"/Sim/Humanoid/Right/Knee/DesiredAngle","value":"25"})", true) +
               Post("/api/live/control", R"({"action":"run"})", true) +
               Post("/api/live/control", R"({"action":"pause"})", true)},
          {"live_files.http", "1" + Post("/api/live/load", R"({"file":"start.val"})", true) +
                                  Post("/api/live/save", R"({"file":"saved.val","filter":".*Knee.*"})", true) +
                                  Post("/api/live/logger", R"({"action":"start","filter":".*Knee/JointAngle","file":"log.csv"})", true) +
                                  Post("/api/live/logger", R"({"action":"stop"})", true)},
          {"live_render.http", "1" + std::string("POST /api/render/frame?index=1 HTTP/1.1\r\nHost: 127.0.0.1\r\n"
                                                 "Content-Length: 12\r\n\r\n\x89PNG\r\n\x1a\n1234") +
                                   Post("/api/render/done", "", false)}};
}

}  // namespace

std::vector<Seed> SeedsFor(const std::string& target, const std::string& source_dir) {
  const fs::path root(source_dir);
  if (target == "environment_xml") return InlinedEnvironments(root);
  if (target == "value_file") return ValueFiles();
  if (target == "motion_record") {
    std::vector<Seed> seeds = FilesIn(root / "scenarios/motions", ".csv");
    for (Seed& seed : FilesIn(root / "scenarios/examples", ".csv")) seeds.push_back(std::move(seed));
    return seeds;
  }
  if (target == "scenario_json") return ResolvedScenarios(root);
  if (target == "broker_message") return BrokerMessages(root);
  if (target == "osp_datagram") return OspSessions();
  if (target == "odcp_datagram") return OdcpSessions();
  if (target == "measured_run") return MeasuredRuns();
  if (target == "view_request") return ViewRequests();
  throw InputError("fuzz seeds", 0, "unknown target '" + target + "'");
}

}  // namespace orcs::fuzz
