// orcs-view --live against what a web page the user visits, or a slow client, can do (issue 47, item 4;
// docs/security.md, "The browser"): the real program on 127.0.0.1, real sockets, each bug as it was seen and now
// refused or bounded.
#include <arpa/inet.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <httplib.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <regex>
#include <thread>

#include "tests/support/background_process.h"
#include "tests/support/temp_dir.h"

namespace orcs {
namespace {

using Clock = std::chrono::steady_clock;
using test_support::BackgroundProcess;
using ::testing::HasSubstr;
using ::testing::Not;

const std::string kView = ORCS_BINARY_DIR "/bin/orcs-view";

double SecondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// orcs-view --live on a free loopback port, with a one-file page and its own files folder.
class LiveView {
 public:
  explicit LiveView(const test_support::TempDir& dir, std::vector<std::string> extra = {}) : files_(dir.PathOf("files")) {
    dir.Write("web/index.html", "<html>orcs-view</html>");
    dir.Write("web/files.txt", "index.html -> index.html\n");
    std::vector<std::string> argv = {kView, "--web-dir", dir.PathOf("web"), "--live", "--port", "0", "--files", files_};
    argv.insert(argv.end(), extra.begin(), extra.end());
    process_ = std::make_unique<BackgroundProcess>(argv);
    const std::optional<std::string> line = process_->ReadLine(std::chrono::seconds(30));
    if (!line) throw std::runtime_error("orcs-view printed no address: " + process_->err());
    std::smatch match;
    if (!std::regex_search(*line, match, std::regex(R"(serving http://127\.0\.0\.1:(\d+)/)"))) {
      throw std::runtime_error("unexpected first line: " + *line);
    }
    port_ = std::stoi(match[1]);
  }

  int port() const { return port_; }
  std::string host() const { return "127.0.0.1:" + std::to_string(port_); }
  std::string origin() const { return "http://" + host(); }
  const std::string& files() const { return files_; }

  httplib::Client Client() const {
    httplib::Client client("127.0.0.1", port_);
    client.set_read_timeout(5, 0);
    client.set_connection_timeout(5, 0);
    return client;
  }

  // Takes control as the page does: a JSON POST from the page's own origin.
  std::string Claim() const {
    const httplib::Result claimed = Client().Post("/api/live/claim", {{"Origin", origin()}}, "{}", "application/json");
    if (!claimed || claimed->status != 200) throw std::runtime_error("claim failed");
    return nlohmann::json::parse(claimed->body)["token"];
  }

  // A controlled POST with the token, as the page sends it.
  httplib::Result Post(const std::string& token, const std::string& path, const nlohmann::json& body) const {
    return Client().Post(path, {{"X-Orcs-Token", token}, {"Origin", origin()}}, body.dump(), "application/json");
  }

  // The live state (GET /api/live/frame without a token: watching does not keep control).
  nlohmann::json State() const {
    const httplib::Result frame = Client().Get("/api/live/frame?since=-1");
    if (!frame || frame->status != 200) throw std::runtime_error("no frame");
    return nlohmann::json::parse(frame->body);
  }

  // Awaits the live state satisfying `done`, reading it until `limit` passes; the last state read.
  template <typename Done>
  nlohmann::json AwaitState(Done done, std::chrono::seconds limit) const {
    const Clock::time_point until = Clock::now() + limit;
    nlohmann::json state = State();
    while (!done(state) && Clock::now() < until) {
      std::this_thread::sleep_for(std::chrono::milliseconds(50));  // a poll interval, not a wait for a condition
      state = State();
    }
    return state;
  }

 private:
  std::string files_;
  std::unique_ptr<BackgroundProcess> process_;
  int port_ = 0;
};

// A connected loopback socket to `port` (-1 when it cannot connect).
int Connect(int port) {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(static_cast<std::uint16_t>(port));
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0) {
    close(fd);
    return -1;
  }
  return fd;
}

// The answer to raw request bytes, read until the server closes or 5 s pass.
std::string RawAnswer(int port, const std::string& bytes) {
  const int fd = Connect(port);
  if (fd < 0) return "";
  (void)!write(fd, bytes.data(), bytes.size());
  std::string answer;
  char buffer[4096];
  pollfd readable{fd, POLLIN, 0};
  while (poll(&readable, 1, 5000) == 1) {
    const ssize_t got = read(fd, buffer, sizeof buffer);
    if (got <= 0) break;
    answer.append(buffer, static_cast<std::size_t>(got));
    if (answer.find("\r\n\r\n") != std::string::npos && answer.find("}") != std::string::npos) break;
  }
  close(fd);
  return answer;
}

std::string ErrorOf(const httplib::Result& result) {
  if (!result) return "(no answer)";
  try {
    return nlohmann::json::parse(result->body).value("error", "");
  } catch (const std::exception&) {
    return result->body;
  }
}

// DNS rebinding: a page of evil.example whose name now points at 127.0.0.1 sends Host: evil.example. It got the
// control token, and with it the simulation, the values, the files and the logger. Now every route refuses it.
TEST(OrcsViewSecurityTest, AForeignHostIsRefusedOnEveryRouteAndGetsNoToken) {
  test_support::TempDir dir;
  const LiveView view(dir);
  const std::string port = std::to_string(view.port());
  for (const std::string& foreign : std::vector<std::string>{"evil.example", "evil.example:" + port, "127.0.0.1:1", "127.0.0.1.evil.example:" + port,
                                     "localhost.:" + port, "127.0.0.1:" + port + "@evil", "[::2]:" + port}) {
    const httplib::Headers headers = {{"Host", foreign}};
    const httplib::Result claim = view.Client().Post("/api/live/claim", headers, "{}", "application/json");
    ASSERT_TRUE(claim) << foreign;
    EXPECT_EQ(claim->status, 403) << foreign;
    EXPECT_THAT(claim->body, Not(HasSubstr("token"))) << foreign;
    EXPECT_THAT(ErrorOf(claim), HasSubstr("is not this server")) << foreign;
    EXPECT_THAT(ErrorOf(claim), HasSubstr("DNS rebinding"));
    for (const char* path : {"/", "/api/session", "/api/live/world", "/api/live/values", "/api/live/files"}) {
      const httplib::Result got = view.Client().Get(path, headers);
      ASSERT_TRUE(got) << foreign << " " << path;
      EXPECT_EQ(got->status, 403) << foreign << " " << path;
    }
  }
  // No Host at all (HTTP/1.0), and two of them, are refused too; the reason is one line.
  const std::string no_host = RawAnswer(view.port(), "GET /api/session HTTP/1.0\r\n\r\n");
  EXPECT_THAT(no_host, ::testing::StartsWith("HTTP/1.1 403 ")) << no_host;
  EXPECT_THAT(no_host, HasSubstr("no Host header"));
  const std::string two = RawAnswer(view.port(), "GET /api/session HTTP/1.1\r\nHost: " + view.host() +
                                                     "\r\nHost: evil.example\r\nConnection: close\r\n\r\n");
  EXPECT_THAT(two, ::testing::StartsWith("HTTP/1.1 403 ")) << two;
  // The server's own names, with its port, are answered; the token goes to them only.
  for (const std::string& own : std::vector<std::string>{view.host(), "localhost:" + port, "LocalHost:" + port, "[::1]:" + port}) {
    const httplib::Result got = view.Client().Get("/api/session", {{"Host", own}});
    ASSERT_TRUE(got) << own;
    EXPECT_EQ(got->status, 200) << own << ": " << got->body;
  }
  EXPECT_EQ(view.Claim().size(), 32u);
}

// Another site's page (no rebinding: Host is right, Origin is the other site) and the page's own routes.
TEST(OrcsViewSecurityTest, AForeignOriginIsRefusedAndStateChangesNeedTheTokenAndJson) {
  test_support::TempDir dir;
  const LiveView view(dir);
  httplib::Client client = view.Client();
  for (const std::string& foreign : std::vector<std::string>{"http://evil.example", "null",
                                     "https://" + view.host(), "http://localhost:" + std::to_string(view.port()),
                                     view.origin() + ".evil.example", view.origin() + "/"}) {
    const httplib::Result claim = client.Post("/api/live/claim", {{"Origin", foreign}}, "{}", "application/json");
    ASSERT_TRUE(claim) << foreign;
    EXPECT_EQ(claim->status, 403) << foreign;
    EXPECT_THAT(ErrorOf(claim), HasSubstr("is not this server's page")) << foreign;
    EXPECT_EQ(claim->get_header_value("Access-Control-Allow-Origin"), "") << "no CORS grant";
    // A cross-origin read (fetch with mode cors) carries Origin on GET too.
    EXPECT_EQ(client.Get("/api/live/values", {{"Origin", foreign}})->status, 403) << foreign;
    // A CORS preflight, which a cross-site JSON POST or a custom header would need first, is refused.
    const httplib::Result preflight = client.Options("/api/live/control", {{"Origin", foreign},
                                                                          {"Access-Control-Request-Method", "POST"}});
    ASSERT_TRUE(preflight);
    EXPECT_EQ(preflight->status, 403);
    EXPECT_EQ(preflight->get_header_value("Access-Control-Allow-Origin"), "");
  }
  // A cross-site form can send only text/plain, a urlencoded or a multipart body: a claim must be JSON.
  for (const char* type : {"text/plain", "application/x-www-form-urlencoded"}) {
    const httplib::Result claim = client.Post("/api/live/claim", "{}", type);
    ASSERT_TRUE(claim);
    EXPECT_EQ(claim->status, 415) << type;
    EXPECT_THAT(claim->body, Not(HasSubstr("token")));
  }
  const httplib::Result multipart = client.Post("/api/live/claim", "--x--\r\n", "multipart/form-data; boundary=x");
  ASSERT_TRUE(multipart);
  EXPECT_GE(multipart->status, 400) << "refused (as 415, or 400 where the library finds the form malformed)";
  EXPECT_THAT(multipart->body, Not(HasSubstr("token")));
  // Requests without Origin (curl, the page's own GETs) are answered; the page's own POSTs carry its origin.
  EXPECT_EQ(client.Get("/api/live/values?filter=.*Knee/JointAngle")->status, 200);
  const std::string token = view.Claim();
  EXPECT_EQ(view.Post(token, "/api/live/control", {{"action", "step"}})->status, 200);
  // The token itself does not help another site's page, nor a non-JSON body.
  EXPECT_EQ(client.Post("/api/live/control", {{"X-Orcs-Token", token}, {"Origin", "http://evil.example"}},
                        R"({"action":"run"})", "application/json")->status, 403);
  EXPECT_EQ(client.Post("/api/live/control", {{"X-Orcs-Token", token}}, R"({"action":"run"})", "text/plain")->status,
            415);
  EXPECT_EQ(view.State()["running"], false) << "nothing ran";
  // Every answer forbids framing (clickjacking on "Take control") and cross-origin embedding.
  const httplib::Result page = client.Get("/");
  EXPECT_EQ(page->get_header_value("X-Frame-Options"), "DENY");
  EXPECT_EQ(page->get_header_value("Content-Security-Policy"), "frame-ancestors 'none'");
  EXPECT_EQ(page->get_header_value("Cross-Origin-Resource-Policy"), "same-origin");
}

// `.*` with real time off wrote 416 MB in 40 s. Now a log stops at its size bound, says why, and the file is
// complete (renamed onto its name) and ends with the truncation line.
TEST(OrcsViewSecurityTest, TheLoggerStopsAtItsSizeBound) {
  test_support::TempDir dir;
  const LiveView view(dir, {"--log-max-mib", "1"});
  const std::string token = view.Claim();
  ASSERT_EQ(view.Post(token, "/api/live/logger", {{"action", "start"}, {"filter", ".*"}, {"file", "all.csv"}})->status,
            200);
  const nlohmann::json before = view.State();
  EXPECT_EQ(before["logger"]["max_bytes"], 1 << 20);
  EXPECT_EQ(before["logger"]["max_seconds"], 600.0);
  const Clock::time_point start = Clock::now();
  ASSERT_EQ(view.Post(token, "/api/live/control", {{"action", "run"}, {"realtime", false}})->status, 200);
  const nlohmann::json state = view.AwaitState(
      [](const nlohmann::json& s) { return s["logger"]["file"].is_null(); }, std::chrono::seconds(20));
  const double seconds = SecondsSince(start);
  ASSERT_TRUE(state["logger"]["file"].is_null()) << state.dump();
  EXPECT_THAT(state["logger"]["stopped"].get<std::string>(), HasSubstr("all.csv stopped: it reached its bound of 1 MiB"));
  const std::string file = view.files() + "/all.csv";
  ASSERT_TRUE(std::filesystem::exists(file));
  const std::uintmax_t size = std::filesystem::file_size(file);
  EXPECT_LE(size, (1u << 20) + 200u) << "the bound, and the truncation line";
  EXPECT_GT(size, (1u << 20) - 64u * 1024u);
  const std::string text = dir.Read(file);
  const std::string last = text.substr(text.rfind('\n', text.size() - 2) + 1);
  EXPECT_THAT(last, ::testing::StartsWith("# log truncated at time ")) << last;
  std::printf("[ measured ] 1 MiB log of .* as fast as possible: stopped after %.2f s, %ju bytes\n", seconds, size);
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // a span in which a runaway log would grow
  EXPECT_EQ(std::filesystem::file_size(file), size) << "nothing written after the stop";
}

// The log also ends after its time bound, paused or running.
TEST(OrcsViewSecurityTest, TheLoggerStopsAfterItsTimeBound) {
  test_support::TempDir dir;
  const LiveView view(dir, {"--log-max-seconds", "1"});
  const std::string token = view.Claim();
  const Clock::time_point start = Clock::now();
  ASSERT_EQ(view.Post(token, "/api/live/logger", {{"action", "start"}, {"filter", ".*Knee/JointAngle"}, {"file", "k.csv"}})
                ->status,
            200);
  const nlohmann::json running = view.State();
  EXPECT_EQ(running["logger"]["file"], "k.csv");
  EXPECT_EQ(running["logger"]["max_seconds"], 1.0);
  const nlohmann::json state = view.AwaitState(
      [](const nlohmann::json& s) { return s["logger"]["file"].is_null(); }, std::chrono::seconds(10));
  const double seconds = SecondsSince(start);
  EXPECT_THAT(state["logger"]["stopped"].get<std::string>(), HasSubstr("its bound of 1 s (--log-max-seconds)"));
  EXPECT_GE(seconds, 1.0);
  EXPECT_LT(seconds, 3.0);
  EXPECT_TRUE(std::filesystem::exists(view.files() + "/k.csv"));
  std::printf("[ measured ] a 1 s log ended %.2f s after its start\n", seconds);
}

// The log kept writing after the token lapsed. Now it ends when its page loses control.
TEST(OrcsViewSecurityTest, TheLoggerStopsWhenControlLapses) {
  test_support::TempDir dir;
  const LiveView view(dir, {"--control-timeout", "1"});
  const std::string token = view.Claim();
  ASSERT_EQ(view.Post(token, "/api/live/control", {{"action", "run"}, {"realtime", true}})->status, 200);
  const Clock::time_point start = Clock::now();
  ASSERT_EQ(view.Post(token, "/api/live/logger", {{"action", "start"}, {"filter", ".*Knee/JointAngle"}, {"file", "k.csv"}})
                ->status,
            200);
  const nlohmann::json state = view.AwaitState(
      [](const nlohmann::json& s) { return s["logger"]["file"].is_null(); }, std::chrono::seconds(10));
  const double seconds = SecondsSince(start);
  EXPECT_THAT(state["logger"]["stopped"].get<std::string>(), HasSubstr("control lapsed"));
  EXPECT_GE(seconds, 1.0);
  EXPECT_LT(seconds, 3.0);
  EXPECT_EQ(view.Post(token, "/api/live/logger", {{"action", "start"}, {"filter", ".*"}, {"file", "x.csv"}})->status, 403)
      << "the lapsed token starts nothing";
  const std::uintmax_t size = std::filesystem::file_size(view.files() + "/k.csv");
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // the simulation runs on: the log must not grow
  EXPECT_EQ(std::filesystem::file_size(view.files() + "/k.csv"), size);
  std::printf("[ measured ] control lapsed after 1 s: the log ended %.2f s after its start\n", seconds);
}

// 12 connections trickling a request (the old pool's size) denied every other request for 37 s. Now 24 trickling
// connections — each sending a header byte every 0.5 s, within the read timeout, so the server keeps them — leave
// the server answering at once; and a connection that sends nothing is dropped after the keep-alive timeout.
TEST(OrcsViewSecurityTest, TricklingConnectionsDoNotDenyService) {
  test_support::TempDir dir;
  const LiveView view(dir);
  constexpr int kTricklers = 24;
  std::vector<int> sockets;
  for (int i = 0; i < kTricklers; ++i) {
    const int fd = Connect(view.port());
    ASSERT_GE(fd, 0);
    const std::string head = "GET /api/session HTTP/1.1\r\nHost: " + view.host() + "\r\nX-Slow: ";
    ASSERT_EQ(write(fd, head.data(), head.size()), static_cast<ssize_t>(head.size()));
    sockets.push_back(fd);
  }
  std::atomic<bool> stop = false;
  std::atomic<int> failed_writes = 0;
  struct Joined {  // stops and joins the trickler however the test ends (an ASSERT returns early)
    std::atomic<bool>& stop;
    std::thread thread;
    ~Joined() {
      stop = true;
      if (thread.joinable()) thread.join();
    }
  } trickler{stop, std::thread([&] {
    while (!stop) {
      for (int fd : sockets) {
        if (send(fd, "a", 1, MSG_NOSIGNAL) != 1) ++failed_writes;
      }
      for (int i = 0; i < 10 && !stop; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
  })};
  // Past the read timeout (2 s), trickling all along: every connection has been taken up by a server thread and
  // kept (a dropped one would fail the later writes).
  std::this_thread::sleep_for(std::chrono::milliseconds(2500));
  double worst = 0.0;
  for (int i = 0; i < 5; ++i) {
    const Clock::time_point start = Clock::now();
    const httplib::Result answer = view.Client().Get("/api/session");
    worst = std::max(worst, SecondsSince(start));
    ASSERT_TRUE(answer) << "request " << i << " got no answer beside " << kTricklers << " trickling connections";
    EXPECT_EQ(answer->status, 200);
  }
  EXPECT_LT(worst, 1.0);
  // An idle connection (nothing sent) is closed by the server after the keep-alive timeout (2 s).
  const int idle = Connect(view.port());
  ASSERT_GE(idle, 0);
  const Clock::time_point idle_start = Clock::now();
  pollfd readable{idle, POLLIN, 0};
  char byte = 0;
  const bool closed = poll(&readable, 1, 6000) == 1 && read(idle, &byte, 1) == 0;
  const double idle_seconds = SecondsSince(idle_start);
  close(idle);
  EXPECT_TRUE(closed);
  EXPECT_LT(idle_seconds, 4.0);
  stop = true;
  trickler.thread.join();
  EXPECT_EQ(failed_writes.load(), 0) << "the trickling connections were held, not dropped";
  for (int fd : sockets) close(fd);
  std::printf("[ measured ] %d trickling connections: a normal request answered in at most %.1f ms; an idle connection "
              "closed after %.2f s\n",
              kTricklers, worst * 1000.0, idle_seconds);
}

// A string value with a line feed was saved as extra lines of a value file, which loading then applied. Now the
// page cannot set it, and a value file with a control character is refused naming the line.
TEST(OrcsViewSecurityTest, AValueWithALineFeedNeverBecomesLinesOfAValueFile) {
  test_support::TempDir dir;
  const LiveView view(dir);
  const std::string token = view.Claim();
  const std::string injected = "PVC\n/Simulation/TimeStepSize=0.1";
  const httplib::Result set = view.Post(token, "/api/live/values", {{"path", "/Sim/Floor/Material"}, {"value", injected}});
  ASSERT_TRUE(set);
  EXPECT_EQ(set->status, 400);
  EXPECT_THAT(ErrorOf(set), HasSubstr("/Sim/Floor/Material: the value holds control character U+000A (line feed)"));
  for (const std::string& bad : std::vector<std::string>{"PVC\r", std::string("P\0VC", 4), "\x1b[2J"}) {
    EXPECT_EQ(view.Post(token, "/api/live/values", {{"path", "/Sim/Floor/Material"}, {"value", bad}})->status, 400);
  }
  ASSERT_EQ(view.Post(token, "/api/live/save", {{"file", "all.val"}, {"filter", ".*"}})->status, 200);
  const std::string saved = dir.Read(view.files() + "/all.val");
  EXPECT_THAT(saved, Not(HasSubstr("TimeStepSize=0.1\n")));
  // A value file that holds one (written by hand, or by an older orcs) is refused, naming its line.
  dir.Write("files/bad.val", "/Sim/Floor/Material=PVC\r/Simulation/TimeStepSize=0.1\n");
  const httplib::Result load = view.Post(token, "/api/live/load", {{"file", "bad.val"}});
  ASSERT_TRUE(load);
  EXPECT_EQ(load->status, 400);
  EXPECT_THAT(ErrorOf(load), HasSubstr("bad.val:1: control character U+000D (carriage return) at column 24"));
  const nlohmann::json step =
      nlohmann::json::parse(view.Client().Get("/api/live/values?filter=^/Simulation/TimeStepSize$")->body);
  ASSERT_EQ(step.size(), 1u);
  EXPECT_NE(step[0]["value"], "0.1") << "nothing applied";
}

}  // namespace
}  // namespace orcs
