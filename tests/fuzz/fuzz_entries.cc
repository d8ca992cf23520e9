#include "tests/fuzz/fuzz_entries.h"

#include <unistd.h>

#include <charconv>
#include <chrono>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <brotli/decode.h>
#include <google/protobuf/stubs/logging.h>
#include <zlib.h>
#include <nlohmann/json.hpp>

#include "model/identify/measured_run.h"
#include "model/control/keyframe_player.h"
#include "model/control/keyframe_record.h"
#include "model/core/error.h"
#include "model/core/json_node.h"
#include "model/core/value_file.h"
#include "model/evaluation/recorder.h"
#include "model/scene/environment_reader.h"
#include "model/scene/scenario.h"
#include "model/scene/simulation.h"
#include "model/scene/world_model.h"
#include "model/scene/world_setup.h"
#include "orcs/v1/broker.pb.h"
#include "proto/envelope.h"
#include "viewer/live_session.h"
#include "viewer/render_sink.h"
#include "viewer/view_catalog.h"
#include "viewer/view_server.h"
#include "viewer/web_assets.h"
#include "model/evaluation/evaluation.h"
#include "worker/job/job_translation.h"
#include "proto/result_json.h"
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
void WriteResult(const v1::Result& result) { [[maybe_unused]] const std::string line = proto::ResultToJson(result).dump(); }

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
    std::optional<identify::ColumnMapping> mapping;
    std::string_view csv = data;
    if (const std::size_t split = data.find("\n---\n"); split != std::string_view::npos) {
      mapping = identify::ParseColumnMapping(ParseJson(std::string(data.substr(0, split)), "fuzz.json"), "fuzz.json");
      csv = data.substr(split + 5);
    }
    const identify::MeasuredRun run = identify::ParseMeasuredRun(csv, "fuzz.csv", mapping ? &*mapping : nullptr);
    identify::CommandsAsRecord(run, run.commanded);
  });
}

namespace {

namespace fs = std::filesystem;

// Marks the file kept beside the opened folders: no answer may ever contain it.
constexpr std::string_view kOutsideMarker = "ORCS-FUZZ-OUTSIDE-5e1c9a";

void WriteText(const fs::path& file, std::string_view text) {
  fs::create_directories(file.parent_path());
  std::ofstream(file, std::ios::binary) << text;
}

// The two orcs-view servers the requests go to, built once per process in a private folder:
//   open/run.orcsrec, open/batch/{results.jsonl, recordings/job-1.orcsrec}   what files mode was given
//   live-files/{start.val, link.val -> ../outside.val}                         the live files folder
//   outside.val                                                                 holds kOutsideMarker
//   web/, render/                                                               the page, the render sink's folder
class ViewFixture {
 public:
  ViewFixture()
      : root_(fs::temp_directory_path() / ("orcs-fuzz-view-" + std::to_string(static_cast<long>(getpid())))),
        assets_(MakeFolders(root_)),
        catalog_({(root_ / "open/run.orcsrec").string(), (root_ / "open/batch").string()}),
        live_(LiveOptionsFor(root_)),
        render_((root_ / "render").string(), 4),
        files_server_(assets_, &catalog_, nullptr, nullptr),
        live_server_(assets_, nullptr, &live_, &render_) {
    // A long poll would make every input that asks for a frame newer than the newest wait; the route is the same.
    files_server_.SetLongPoll(std::chrono::milliseconds(0));
    live_server_.SetLongPoll(std::chrono::milliseconds(0));
    token_ = live_.Claim();
    Require(!token_.empty(), "the fixture could not take control of the live session");
  }
  ~ViewFixture() {
    std::error_code ignored;
    fs::remove_all(root_, ignored);
  }

  viewer::ViewServer& files_server() { return files_server_; }
  viewer::ViewServer& live_server() { return live_server_; }
  const std::string& token() const { return token_; }

  // Keeps control (an input may have been slow) and brings the live session back to where every input starts:
  // paused, no logger, reset, and no files but the fixture's in its files folder.
  void Restore() {
    if (!live_.Controls(token_)) token_ = live_.Claim();
    live_.StopLogger();
    live_.Control("reset", true);
    std::error_code error;
    for (const fs::directory_entry& entry : fs::directory_iterator(root_ / "live-files", error)) {
      const std::string name = entry.path().filename().string();
      if (name != "start.val" && name != "link.val") fs::remove_all(entry.path(), error);
    }
  }

 private:
  static std::string MakeFolders(const fs::path& root) {
    fs::create_directories(root);
    WriteText(root / "web/index.html", "<html>orcs-view</html>");
    WriteText(root / "web/app.js", "export const app = 1;");
    WriteText(root / "web/files.txt", "index.html -> index.html\napp.js -> app.js\n");
    WriteText(root / "outside.val", std::string("#ORCS Values\n") + std::string(kOutsideMarker) + "\n");
    WriteText(root / "live-files/start.val", "#ORCS Values\n/Sim/Humanoid/Right/Knee/DesiredAngle=20\n");
    std::error_code ignored;
    fs::create_symlink("../outside.val", root / "live-files/link.val", ignored);
    fs::create_directories(root / "render");
    WriteRecordingTo(root / "open/run.orcsrec");
    WriteRecordingTo(root / "open/batch/recordings/job-1.orcsrec");
    WriteText(root / "open/batch/results.jsonl",
              R"({"id":"job-1","status":"ok","fitness":1.5,"seed":7,"terms":{"distance":1.5},"message":""})" "\n");
    return (root / "web").string();
  }

  static void WriteRecordingTo(const fs::path& file) {
    fs::create_directories(file.parent_path());
    scene::Simulation simulation;
    scene::SetUpWorld(simulation, "", {}, {});
    simulation.Reset(0);
    evaluation::Recorder recorder(simulation, evaluation::RecordingSource{});
    for (int i = 0; i < 3; ++i) {
      simulation.Step();
      recorder.Sample();
    }
    evaluation::WriteRecording(file.string(), recorder.Finish());
  }

  static viewer::LiveOptions LiveOptionsFor(const fs::path& root) {
    viewer::LiveOptions options;
    options.files_dir = (root / "live-files").string();
    return options;
  }

  fs::path root_;
  viewer::WebAssets assets_;
  viewer::ViewCatalog catalog_;
  viewer::LiveSession live_;
  viewer::RenderSink render_;
  viewer::ViewServer files_server_;
  viewer::ViewServer live_server_;
  std::string token_;
};

ViewFixture& View() {
  static ViewFixture fixture;
  return fixture;
}

std::string ReplaceAll(std::string text, std::string_view from, const std::string& to) {
  for (std::size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size())) {
    text.replace(at, from.size(), to);
  }
  return text;
}

struct HttpAnswer {
  int status = 0;
  std::string body;
  bool head_only = false;  ///< a HEAD answer: Content-Length announced, no body sent
};

// A body as sent with Content-Encoding `encoding` (httplib compresses when the request accepts it, as browsers
// do), decoded so that the checks see what a browser would; aborts when it does not decode.
std::string Decoded(const std::string& body, const std::string& encoding) {
  if (encoding.empty() || body.empty()) return body;
  std::string out(std::size_t{4} << 20, '\0');  // the fixture's answers are far smaller
  if (encoding == "br") {
    std::size_t size = out.size();
    Require(BrotliDecoderDecompress(body.size(), reinterpret_cast<const std::uint8_t*>(body.data()), &size,
                                    reinterpret_cast<std::uint8_t*>(out.data())) == BROTLI_DECODER_RESULT_SUCCESS,
            "a brotli answer does not decode");
    out.resize(size);
    return out;
  }
  Require(encoding == "gzip" || encoding == "deflate", "an answer has an unknown Content-Encoding");
  z_stream stream{};
  Require(inflateInit2(&stream, encoding == "gzip" ? 16 + MAX_WBITS : MAX_WBITS) == Z_OK, "inflateInit2 failed");
  stream.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(body.data()));
  stream.avail_in = static_cast<uInt>(body.size());
  stream.next_out = reinterpret_cast<Bytef*>(out.data());
  stream.avail_out = static_cast<uInt>(out.size());
  const int result = inflate(&stream, Z_FINISH);
  inflateEnd(&stream);
  Require(result == Z_STREAM_END, "a compressed answer does not decode");
  out.resize(stream.total_out);
  return out;
}

// What the server wrote back for one request, aborting unless it is well-formed: "HTTP/1.1 DDD reason", header
// lines, an empty line, and Content-Length bytes of body (none after a HEAD); interim 100 Continue heads first.
HttpAnswer ParseAnswer(std::string_view bytes) {
  while (true) {
    const std::size_t head_end = bytes.find("\r\n\r\n");
    Require(head_end != std::string_view::npos, "a request got no answer, or one whose head does not end");
    const std::string_view head = bytes.substr(0, head_end);
    const auto digit = [&](std::size_t k) { return std::isdigit(static_cast<unsigned char>(head[k])) != 0; };
    Require(head.size() >= 13 && head.substr(0, 9) == "HTTP/1.1 " && digit(9) && digit(10) && digit(11) &&
                head[12] == ' ',
            "an answer does not start with an HTTP/1.1 status line");
    HttpAnswer answer;
    answer.status = (head[9] - '0') * 100 + (head[10] - '0') * 10 + (head[11] - '0');
    std::size_t length = 0;
    std::string encoding;
    for (std::size_t at = head.find("\r\n"); at != std::string_view::npos;) {
      const std::size_t next = head.find("\r\n", at + 2);
      const std::string_view line = head.substr(at + 2, next == std::string_view::npos ? next : next - at - 2);
      Require(line.find(": ") != std::string_view::npos && line.find('\n') == std::string_view::npos,
              "an answer has a malformed header line");
      if (line.substr(0, 16) == "Content-Length: ") {
        const auto [end, error] = std::from_chars(line.data() + 16, line.data() + line.size(), length);
        Require(error == std::errc() && end == line.data() + line.size(), "an answer has a bad Content-Length");
      }
      if (line.substr(0, 18) == "Content-Encoding: ") encoding = std::string(line.substr(18));
      at = next;
    }
    bytes.remove_prefix(head_end + 4);
    if (answer.status == 100) continue;
    Require(bytes.size() == length || bytes.empty(), "an answer's body is not Content-Length bytes long");
    answer.head_only = bytes.empty() && length > 0;
    answer.body = Decoded(std::string(bytes), encoding);
    return answer;
  }
}

// A 4xx answer's error: a JSON {"error": "..."} or a plain line; aborts unless it is one non-empty line.
std::string ErrorLine(const HttpAnswer& answer) {
  std::string error = answer.body;
  if (!error.empty() && error.front() == '{') {
    const nlohmann::json body = nlohmann::json::parse(error, nullptr, false);
    Require(body.is_object() && body.contains("error") && body["error"].is_string(),
            "a JSON error answer has no \"error\" string");
    error = body["error"].get<std::string>();
  } else if (!error.empty() && error.back() == '\n') {
    error.pop_back();
  }
  Require(!error.empty() && error.find('\n') == std::string::npos && error.find('\r') == std::string::npos,
          "an error answer is not one non-empty line");
  return std::to_string(answer.status) + " " + error;
}

}  // namespace

FeedResult FeedViewRequest(std::string_view data) {
  ViewFixture& fixture = View();
  if (data.empty()) return {};
  viewer::ViewServer& server = data[0] % 2 == 0 ? fixture.files_server() : fixture.live_server();
  const std::string request = ReplaceAll(std::string(data.substr(1)), "@token@", fixture.token());
  const std::vector<std::string> written = server.Answer(request);
  fixture.Restore();
  Require(request.empty() || !written.empty(), "a request got no answer");
  FeedResult result;
  for (const std::string& bytes : written) {
    Require(bytes.find(kOutsideMarker) == std::string::npos, "an answer holds a file from outside the opened folders");
    const HttpAnswer answer = ParseAnswer(bytes);
    Require((answer.status >= 200 && answer.status < 300) || (answer.status >= 400 && answer.status < 500),
            "an answer's status is neither 2xx nor 4xx");
    Require(answer.body.find(kOutsideMarker) == std::string::npos,
            "a compressed answer holds a file from outside the opened folders");
    if (answer.status < 400) continue;
    // A HEAD answer announces its error but sends none (httplib, as HTTP says): only its status can be checked.
    const std::string error =
        answer.head_only ? std::to_string(answer.status) + " (an answer to HEAD, without its body)" : ErrorLine(answer);
    if (result.accepted) result = {false, error};
  }
  return result;
}

const std::vector<FuzzTarget>& FuzzTargets() {
  static const std::vector<FuzzTarget> targets = {
      {"environment_xml", FeedEnvironmentXml}, {"value_file", FeedValueFile},
      {"motion_record", FeedMotionRecord},     {"scenario_json", FeedScenarioJson},
      {"broker_message", FeedBrokerMessage},   {"osp_datagram", FeedOspDatagrams},
      {"odcp_datagram", FeedOdcpDatagrams},    {"measured_run", FeedMeasuredRun},
      {"view_request", FeedViewRequest},
  };
  return targets;
}

}  // namespace orcs::fuzz
