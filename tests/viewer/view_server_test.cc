// ViewServer over real loopback sockets: what it serves, what it refuses, and that it stays up.
#include "viewer/view_server.h"

#include <arpa/inet.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <httplib.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <thread>

#include "model/evaluation/recorder.h"
#include "model/scene/world_setup.h"
#include "tests/support/temp_dir.h"

namespace orcs::viewer {
namespace {

using ::testing::HasSubstr;

constexpr int kSteps = 40;

std::string WriteRecording(const test_support::TempDir& dir, const std::string& name, int steps = kSteps) {
  scene::Simulation simulation;
  scene::SetUpWorld(simulation, "", {}, {});
  simulation.Reset(0);
  simulation.repository().Set("/Sim/Humanoid/Right/Knee/DesiredAngle", "30");
  evaluation::Recorder recorder(simulation, evaluation::RecordingSource{});
  for (int i = 0; i < steps; ++i) {
    simulation.Step();
    recorder.Sample();
  }
  const std::string path = dir.PathOf(name);
  evaluation::WriteRecording(path, recorder.Finish());
  return path;
}

// A web folder with a page and one script, as files.txt lists them.
std::string WriteWebDir(const test_support::TempDir& dir) {
  dir.Write("web/index.html", "<html>orcs-view</html>");
  dir.Write("web/src/app.js", "export const app = 1;");
  dir.Write("web/files.txt", "# test page\nindex.html -> index.html\nsrc/app.js -> app.js\n");
  return dir.PathOf("web");
}

// A server on an ephemeral loopback port, serving in a thread for the test's life.
class Served {
 public:
  Served(const std::string& web, ViewCatalog* catalog, LiveSession* live)
      : assets_(web), server_(assets_, catalog, live, nullptr) {
    port_ = server_.Bind("127.0.0.1", 0);
    thread_ = std::thread([this] { server_.Serve(); });
  }
  ~Served() {
    server_.Stop();
    thread_.join();
  }
  httplib::Client Client() const {
    httplib::Client client("127.0.0.1", port_);
    client.set_read_timeout(5, 0);
    return client;
  }
  int port() const { return port_; }
  std::string host() const { return "127.0.0.1:" + std::to_string(port_); }

 private:
  WebAssets assets_;
  ViewServer server_;
  int port_ = 0;
  std::thread thread_;
};

// Sends raw bytes and returns the start of the answer, up to 4 KiB ("" when the connection closed without one).
std::string RawAnswer(int port, const std::string& bytes) {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(static_cast<std::uint16_t>(port));
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0) {
    close(fd);
    return "";
  }
  timeval timeout{5, 0};
  setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);
  (void)!write(fd, bytes.data(), bytes.size());
  std::string answer;
  char buffer[4096];
  ssize_t got = 0;
  while (answer.size() < sizeof buffer && (got = read(fd, buffer, sizeof buffer - answer.size())) > 0) {
    answer.append(buffer, static_cast<std::size_t>(got));
    const std::size_t head_end = answer.find("\r\n\r\n");
    const std::size_t length_at = answer.find("Content-Length: ");
    if (head_end != std::string::npos && length_at != std::string::npos &&
        answer.size() >= head_end + 4 + std::stoul(answer.substr(length_at + 16))) {
      break;
    }
  }
  close(fd);
  return answer;
}

// Sends raw bytes and returns the status line of the answer ("" when the connection closed without one).
std::string RawRequest(int port, const std::string& bytes) {
  const std::string answer = RawAnswer(port, bytes);
  return answer.substr(0, answer.find("\r\n"));
}

class ViewServerTest : public ::testing::Test {
 protected:
  test_support::TempDir dir_;
  std::string web_ = WriteWebDir(dir_);
  std::string recording_ = WriteRecording(dir_, "run.orcsrec");
};

TEST_F(ViewServerTest, ServesThePageAndTheListedAssetsOnly) {
  ViewCatalog catalog({recording_});
  Served served(web_, &catalog, nullptr);
  httplib::Client client = served.Client();
  EXPECT_EQ(client.Get("/")->body, "<html>orcs-view</html>");
  EXPECT_EQ(client.Get("/assets/app.js")->body, "export const app = 1;");
  EXPECT_EQ(client.Get("/assets/app.js")->get_header_value("Content-Type"), "text/javascript; charset=utf-8");
  EXPECT_EQ(client.Get("/assets/files.txt")->status, 404);
  EXPECT_EQ(client.Get("/assets/index.html.bak")->status, 404);
}

TEST_F(ViewServerTest, PathTraversalAndAbsolutePathsAnswer404) {
  ViewCatalog catalog({recording_});
  Served served(web_, &catalog, nullptr);
  httplib::Client client = served.Client();
  for (const char* path : {"/../run.orcsrec", "/assets/../files.txt", "/assets/..%2Ffiles.txt", "/assets/%2e%2e/files.txt",
                           "/etc/passwd", "//etc/passwd", "/assets//etc/passwd", "/assets/src/app.js",
                           "/api/recording/..%2F..%2Frun.orcsrec", "/api/recording/r0/../../files.txt",
                           "/api/recording//tmp/x"}) {
    const httplib::Result result = client.Get(path);
    ASSERT_TRUE(result) << path;
    EXPECT_EQ(result->status, 404) << path;
  }
  // The same through a raw socket, where no client library normalises the path first.
  EXPECT_EQ(RawRequest(served.port(), "GET /../../../../etc/passwd HTTP/1.1\r\nHost: " + served.host() + "\r\n\r\n").substr(9, 3),
            "404");
}

TEST_F(ViewServerTest, MalformedRequestsAnswer4xx) {
  ViewCatalog catalog({recording_});
  Served served(web_, &catalog, nullptr);
  const std::string garbage = RawRequest(served.port(), "\x16\x03\x01 not http at all\r\n\r\n");
  EXPECT_THAT(garbage, HasSubstr(" 4")) << garbage;
  const std::string no_version = RawRequest(served.port(), "GET\r\n\r\n");
  EXPECT_THAT(no_version, HasSubstr(" 4")) << no_version;
  httplib::Client client = served.Client();
  EXPECT_EQ(client.Get("/api/recording/r0/channels?ids=1,x")->status, 400);
  EXPECT_EQ(client.Get("/api/recording/r0/channels?ids=999999")->status, 400);
  EXPECT_EQ(client.Get("/api/recording/r0/channels")->status, 400);
  EXPECT_EQ(client.Get("/api/recording/r9")->status, 404);
  EXPECT_EQ(client.Post("/api/live/claim", "", "application/json")->status, 404) << "no live session in files mode";
  const std::string huge(2 << 20, 'x');
  const httplib::Result too_big = client.Post("/api/render/done", huge, "text/plain");
  ASSERT_TRUE(too_big);
  EXPECT_EQ(too_big->status, 413);
}

TEST_F(ViewServerTest, ChannelsComeBackAsTheRecordingHoldsThem) {
  ViewCatalog catalog({recording_});
  Served served(web_, &catalog, nullptr);
  httplib::Client client = served.Client();
  const nlohmann::json header = nlohmann::json::parse(client.Get("/api/recording/r0")->body);
  EXPECT_EQ(header["frames"], kSteps + 1);
  EXPECT_DOUBLE_EQ(header["duration"].get<double>(), kSteps * 0.01);
  const auto recording = catalog.Recording("r0");
  const int knee = recording->FindChannel("/Sim/Humanoid/Right/Knee/JointAngle");
  const int time = recording->FindChannel("/Simulation/CurrentSimulationTime");
  const std::string body =
      client.Get(("/api/recording/r0/channels?ids=" + std::to_string(knee) + "," + std::to_string(time)).c_str())->body;
  ASSERT_EQ(body.size(), 2u * (kSteps + 1) * sizeof(float));
  std::vector<float> columns(2 * (kSteps + 1));
  std::memcpy(columns.data(), body.data(), body.size());
  EXPECT_EQ(columns[kSteps], recording->value(kSteps, knee));
  EXPECT_GT(columns[kSteps], 5.0f) << "the knee moved";
  EXPECT_FLOAT_EQ(columns[2 * kSteps + 1], kSteps * 0.01f);
  const std::string times = client.Get("/api/recording/r0/times")->body;
  ASSERT_EQ(times.size(), (kSteps + 1) * sizeof(double));
  const nlohmann::json contacts = nlohmann::json::parse(client.Get("/api/recording/r0/contacts")->body);
  EXPECT_EQ(contacts["offsets"].size(), static_cast<std::size_t>(kSteps + 2));
}

TEST_F(ViewServerTest, StaysUpUnderABoundedFloodOfRequests) {
  ViewCatalog catalog({recording_});
  Served served(web_, &catalog, nullptr);
  constexpr int kClients = 8;
  constexpr int kRequestsEach = 250;
  std::atomic<int> answered{0};
  std::vector<std::thread> clients;
  for (int c = 0; c < kClients; ++c) {
    clients.emplace_back([&, c] {
      httplib::Client client = served.Client();
      for (int i = 0; i < kRequestsEach; ++i) {
        const char* path = (i + c) % 3 == 0 ? "/api/session" : (i + c) % 3 == 1 ? "/../x" : "/api/recording/r0/times";
        if (client.Get(path)) ++answered;
      }
    });
  }
  for (std::thread& client : clients) client.join();
  EXPECT_EQ(answered.load(), kClients * kRequestsEach);
  const httplib::Result after = served.Client().Get("/api/session");
  ASSERT_TRUE(after);
  EXPECT_EQ(after->status, 200);
}

TEST_F(ViewServerTest, LiveModeObeysOnlyTheControllingPage) {
  LiveOptions options;
  options.files_dir = dir_.PathOf("files");
  LiveSession live(options);
  Served served(web_, nullptr, &live);
  httplib::Client watcher = served.Client();
  const nlohmann::json denied = {{"path", "/Sim/Humanoid/Right/Knee/DesiredAngle"}, {"value", "25"}};
  EXPECT_EQ(watcher.Post("/api/live/values", denied.dump(), "application/json")->status, 403);

  const nlohmann::json claim = nlohmann::json::parse(watcher.Post("/api/live/claim", "", "application/json")->body);
  const std::string token = claim["token"];
  EXPECT_EQ(token.size(), 32u);
  EXPECT_EQ(watcher.Post("/api/live/claim", "", "application/json")->status, 409) << "one page controls";
  const httplib::Headers headers = {{"X-Orcs-Token", token}};
  const httplib::Result set = watcher.Post("/api/live/values", headers, denied.dump(), "application/json");
  ASSERT_EQ(set->status, 200) << set->body;
  const nlohmann::json values = nlohmann::json::parse(watcher.Get("/api/live/values?filter=.*Right/Knee/DesiredAngle")->body);
  ASSERT_EQ(values.size(), 1u);
  EXPECT_EQ(values[0]["value"], "25");
  const nlohmann::json bad = {{"path", "/Sim/Humanoid/Right/Knee/DesiredAngle"}, {"value", "abc"}};
  const httplib::Result refused = watcher.Post("/api/live/values", headers, bad.dump(), "application/json");
  EXPECT_EQ(refused->status, 400);
  EXPECT_THAT(refused->body, HasSubstr("DesiredAngle"));
  const nlohmann::json traversal = {{"file", "../escape.val"}};
  EXPECT_EQ(watcher.Post("/api/live/save", headers, traversal.dump(), "application/json")->status, 400);
  EXPECT_EQ(watcher.Get("/api/live/values?filter=(.*)*(.*)*(.*)*(.*)*(.*)*X")->body, "[]") << "RE2: no hang";
}

// A "realtime" that is not a boolean made nlohmann::json throw a type_error, which the server answered as a 500
// internal error (the input is kept in tests/fuzz/regressions/view_request/).
TEST_F(ViewServerTest, ARealtimeThatIsNotABooleanIs400NamingTheField) {
  LiveOptions options;
  options.files_dir = dir_.PathOf("files");
  LiveSession live(options);
  Served served(web_, nullptr, &live);
  httplib::Client client = served.Client();
  const std::string token = nlohmann::json::parse(client.Post("/api/live/claim", "", "application/json")->body)["token"];
  const httplib::Headers headers = {{"X-Orcs-Token", token}};
  for (const char* body : {R"({"action":"run","realtime":"yes"})", R"({"action":"step","realtime":1})",
                           R"({"action":"pause","realtime":null})"}) {
    const httplib::Result result = client.Post("/api/live/control", headers, body, "application/json");
    ASSERT_TRUE(result) << body;
    EXPECT_EQ(result->status, 400) << body << " -> " << result->body;
    EXPECT_THAT(result->body, HasSubstr("realtime: expected true or false")) << body;
  }
  EXPECT_EQ(live.State()["running"], false) << "nothing was run";
  EXPECT_EQ(client.Post("/api/live/control", headers, R"({"action":"step","realtime":false})", "application/json")->status,
            200);
}

// A symbolic link in the live files folder named a file anywhere on the machine, and load applied it (or quoted its
// lines in the error): only the folder's own files are used, and links are not listed.
TEST_F(ViewServerTest, ASymlinkInTheFilesFolderIsNeitherLoadedNorListed) {
  const std::string outside = dir_.Write("outside.val", "#ORCS Values\n/Sim/Humanoid/Right/Knee/DesiredAngle=33\n");
  dir_.Write("files/own.val", "#ORCS Values\n/Sim/Humanoid/Right/Knee/DesiredAngle=12\n");
  std::filesystem::create_symlink(outside, dir_.PathOf("files/link.val"));
  dir_.Write("secret.txt", "TOP-SECRET-LINE\n");
  std::filesystem::create_symlink(dir_.PathOf("secret.txt"), dir_.PathOf("files/secret.val"));
  LiveOptions options;
  options.files_dir = dir_.PathOf("files");
  LiveSession live(options);
  Served served(web_, nullptr, &live);
  httplib::Client client = served.Client();
  const std::string token = nlohmann::json::parse(client.Post("/api/live/claim", "", "application/json")->body)["token"];
  const httplib::Headers headers = {{"X-Orcs-Token", token}};
  EXPECT_EQ(nlohmann::json::parse(client.Get("/api/live/files")->body), nlohmann::json::array({"own.val"}));
  for (const char* link : {"link.val", "secret.val"}) {
    const httplib::Result load =
        client.Post("/api/live/load", headers, nlohmann::json{{"file", link}}.dump(), "application/json");
    ASSERT_TRUE(load);
    EXPECT_EQ(load->status, 400) << link << ": " << load->body;
    EXPECT_THAT(load->body, HasSubstr("symbolic link")) << link;
    EXPECT_THAT(load->body, ::testing::Not(HasSubstr("TOP-SECRET"))) << link;
  }
  const auto knee = [&] {
    return nlohmann::json::parse(client.Get("/api/live/values?filter=.*Right/Knee/DesiredAngle")->body)[0]["value"];
  };
  EXPECT_NE(knee(), "33") << "the linked file was applied";
  EXPECT_EQ(client.Post("/api/live/load", headers, R"({"file":"own.val"})", "application/json")->status, 200);
  EXPECT_EQ(knee(), "12");
}

// ids may repeat, so ~4000 of them (as many as fit in a request line) asked for ~4000 columns of every frame: 17 MB
// for an 1100-frame recording, 1.6 GB for 100,000 frames, per request, on each of the server's threads. The answer
// is bounded at 2^22 values.
TEST_F(ViewServerTest, ChannelAnswersAreBoundedEvenWhenIdsRepeat) {
  const std::string long_run = WriteRecording(dir_, "long.orcsrec", 1100);
  ViewCatalog catalog({long_run});
  Served served(web_, &catalog, nullptr);
  httplib::Client client = served.Client();
  std::string ids = "0";
  for (int i = 1; i < 4000; ++i) ids += ",0";
  // Raw, so that no client library percent-encodes the commas and the line stays under httplib's 8 KiB.
  const std::string many =
      RawAnswer(served.port(), "GET /api/recording/r0/channels?ids=" + ids + " HTTP/1.1\r\nHost: " + served.host() + "\r\n\r\n");
  EXPECT_THAT(many, ::testing::StartsWith("HTTP/1.1 400 "));
  EXPECT_THAT(many, HasSubstr("ids: at most 3809 channels of this recording (1101 frames) per request"));
  const httplib::Result two = client.Get("/api/recording/r0/channels?ids=0,0");
  ASSERT_TRUE(two);
  EXPECT_EQ(two->status, 200);
  EXPECT_EQ(two->body.size(), 2u * 1101u * sizeof(float));
}

// A filter is any bytes after percent-decoding: one that is not UTF-8 made the error message unprintable as JSON, and
// the exception thrown from the exception handler ended orcs-view (std::terminate). Now a 400, and it serves on.
TEST_F(ViewServerTest, AFilterThatIsNotUtf8Is400AndTheServerServesOn) {
  LiveOptions options;
  options.files_dir = dir_.PathOf("files");
  LiveSession live(options);
  Served served(web_, nullptr, &live);
  const std::string status = RawRequest(served.port(), "GET /api/live/values?filter=%FF( HTTP/1.1\r\nHost: " + served.host() + "\r\n\r\n");
  EXPECT_EQ(status, "HTTP/1.1 400 Bad Request");
  httplib::Client client = served.Client();
  const httplib::Result valid_but_not_utf8 = client.Get("/api/live/values?filter=%FF");
  ASSERT_TRUE(valid_but_not_utf8);
  EXPECT_EQ(valid_but_not_utf8->status, 400) << valid_but_not_utf8->body;
  const httplib::Result after = client.Get("/api/session");
  ASSERT_TRUE(after) << "the server is gone";
  EXPECT_EQ(after->status, 200);
}

// Answer() is the server's own handling on bytes: the same routes and refusals as over a socket, one answer per
// request of a keep-alive connection.
TEST_F(ViewServerTest, AnswerHandlesAConnectionsRequestsAsTheSocketDoes) {
  ViewCatalog catalog({recording_});
  const WebAssets assets(web_);
  ViewServer server(assets, &catalog, nullptr, nullptr);
  const std::vector<std::string> answers = server.Answer(
      "GET /api/session HTTP/1.1\r\nHost: localhost\r\n\r\nGET /../../etc/passwd HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n"
      "GET /api/recording/r0/channels?ids=1,x HTTP/1.1\r\nHost: 127.0.0.1:8765\r\n\r\n"
      "GET /api/session HTTP/1.1\r\nHost: x\r\n\r\n");
  ASSERT_EQ(answers.size(), 4u);
  EXPECT_THAT(answers[0], ::testing::StartsWith("HTTP/1.1 200 OK\r\n"));
  EXPECT_THAT(answers[0], HasSubstr(R"("mode":"files")"));
  EXPECT_THAT(answers[1], ::testing::StartsWith("HTTP/1.1 404 "));
  EXPECT_THAT(answers[2], ::testing::StartsWith("HTTP/1.1 400 "));
  EXPECT_THAT(answers[2], HasSubstr("ids: expected channel indices"));
  EXPECT_THAT(answers[3], ::testing::StartsWith("HTTP/1.1 403 ")) << "a name that is not the server's, unbound too";
}

// The first frame at or beyond `step`, awaited frame by frame (each wait bounded).
LiveFrame FrameAtStep(LiveSession& live, std::int64_t step) {
  LiveFrame frame = live.FrameAfter(-1, std::chrono::milliseconds(0));
  for (int tries = 0; frame.step < step && tries < 1000; ++tries) {
    frame = live.FrameAfter(frame.serial, std::chrono::milliseconds(1000));
  }
  return frame;
}

TEST_F(ViewServerTest, LiveStepsWhenToldAndStandsStillWhenPaused) {
  LiveOptions options;
  options.files_dir = dir_.PathOf("files");
  LiveSession live(options);
  EXPECT_EQ(live.FrameAfter(-1, std::chrono::milliseconds(0)).step, 0);
  live.Control("step", true);
  EXPECT_EQ(FrameAtStep(live, 1).step, 1);
  live.Control("run", false);
  EXPECT_GE(FrameAtStep(live, 20).step, 20);
  live.Control("pause", true);
  const LiveFrame paused = live.FrameAfter(-1, std::chrono::milliseconds(0));
  const LiveFrame later = live.FrameAfter(paused.serial, std::chrono::milliseconds(200));
  EXPECT_EQ(later.step, paused.step) << "no step while paused";
  EXPECT_EQ(later.time, paused.time);
  live.Control("reset", true);
  EXPECT_EQ(live.State()["step"], 0);
}

// Simulation Properties' write of a structure value (issue 48): taken at once, applied at the reset, which
// compiles the world anew; the world header (made from the physics model) then has the new size, and the frames
// say that the world changed so that the page draws it again.
TEST_F(ViewServerTest, AStructureValueWrittenLiveChangesTheWorldAtTheReset) {
  LiveOptions options;
  options.files_dir = dir_.PathOf("files");
  LiveSession live(options);
  Served served(web_, nullptr, &live);
  httplib::Client page = served.Client();
  const nlohmann::json claim = nlohmann::json::parse(page.Post("/api/live/claim", "", "application/json")->body);
  const httplib::Headers headers = {{"X-Orcs-Token", claim["token"].get<std::string>()}};
  const auto tibia_height = [&] {
    const nlohmann::json world = nlohmann::json::parse(page.Get("/api/live/world")->body);
    for (const nlohmann::json& body : world["bodies"]) {
      if (body["name"] == "Humanoid/Right/Tibia") return body["geoms"][0]["size"][1].get<double>();
    }
    return -1.0;
  };
  const auto revision = [&] {
    return nlohmann::json::parse(page.Get("/api/live/frame?since=-1", headers)->body)["world_revision"].get<int>();
  };
  EXPECT_DOUBLE_EQ(tibia_height(), 0.049);
  const int before = revision();
  const nlohmann::json longer = {{"path", "/Sim/Humanoid/Right/Tibia/Height"}, {"value", "0.08"}};
  const httplib::Result set = page.Post("/api/live/values", headers, longer.dump(), "application/json");
  ASSERT_EQ(set->status, 200) << set->body;
  EXPECT_DOUBLE_EQ(tibia_height(), 0.049) << "until the reset";
  const nlohmann::json reset = {{"action", "reset"}};
  ASSERT_EQ(page.Post("/api/live/control", headers, reset.dump(), "application/json")->status, 200);
  EXPECT_DOUBLE_EQ(tibia_height(), 0.08);
  EXPECT_EQ(revision(), before + 1);
  const nlohmann::json too_heavy = {{"path", "/Sim/Humanoid/Right/Foot/Mass"}, {"value", "5000"}};
  const httplib::Result refused = page.Post("/api/live/values", headers, too_heavy.dump(), "application/json");
  EXPECT_EQ(refused->status, 400);
  EXPECT_THAT(refused->body, HasSubstr("expected a number from 1e-06 to 1000"));
}

}  // namespace
}  // namespace orcs::viewer
