// ODCP 1.0 over real UDP sockets on 127.0.0.1, spoken by a client written from docs/spec/osp.md alone:
// orcs-osp's per-agent servers (set motor words, step through OSP, read the angles back; bad datagrams),
// orcs-sim --realtime -port, and orcs-sniffer, whose record replayed with orcs-sim -play is compared with the
// replay of the motion that was sent.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <csignal>
#include <cmath>
#include <map>
#include <fstream>
#include <limits>
#include <optional>
#include <regex>
#include <sstream>
#include <thread>

#include "tests/support/background_process.h"
#include "tests/support/process.h"
#include "tests/support/temp_dir.h"
#include "tests/support/udp_peer.h"

namespace orcs {
namespace {

using std::chrono::milliseconds;
using test_support::BackgroundProcess;
using test_support::ProcessResult;
using test_support::RunProcess;
using Bytes = std::vector<std::uint8_t>;
using Clock = std::chrono::steady_clock;

const std::string kBin = ORCS_BINARY_DIR "/bin/";
constexpr int kMotors = 21;
// Motor indices in the order of spec/aseries.md §4c.
constexpr int kRightShoulderYaw = 1;
constexpr int kLeftShoulderYaw = 2;
constexpr int kRightElbow = 5;
constexpr int kLeftElbow = 6;
// The angle sensor's noise, σ in degrees (spec/aseries.md §6d).
constexpr double kSensorNoiseDegrees = 0.189076;

constexpr const char* kTwoRobots = R"xml(<?xml version="1.0"?>
<ORCS version="1.0">
  <Agent>
    <ASeries name="Humanoid" position="(0, 0.001, 0)"/>
    <ASeries name="SecondASeries" position="(1, 0.001, 0)"/>
  </Agent>
</ORCS>
)xml";

// ---- The spec's ODCP: int32 little-endian words; w ↔ n = −1 + 2w/1023; angle 150·n°, torque (n+1)/2. ----
std::int32_t AngleWord(double degrees) {
  return static_cast<std::int32_t>(std::lround((degrees / 150.0 + 1.0) * 511.5));
}
double AngleOf(std::int32_t word) { return 150.0 * (-1.0 + 2.0 * word / 1023.0); }
double TorqueOf(std::int32_t word) { return word / 1023.0; }
constexpr std::int32_t kCentre = 512;         // 0° (n = 1/1023)
constexpr std::int32_t kDefaultTorque = 600;  // 0.5865 of the maximum, the reset value's word
constexpr std::int32_t kFullTorque = 1023;

Bytes Message(std::uint8_t code, const std::vector<std::int32_t>& ints = {}) {
  Bytes bytes{code};
  for (std::int32_t v : ints) {
    for (int i = 0; i < 4; ++i) bytes.push_back(static_cast<std::uint8_t>(static_cast<std::uint32_t>(v) >> (8 * i)));
  }
  return bytes;
}

std::vector<std::int32_t> Ints(const Bytes& bytes, std::size_t from = 1) {
  std::vector<std::int32_t> ints;
  for (std::size_t at = from; at + 4 <= bytes.size(); at += 4) {
    std::uint32_t v = 0;
    for (int i = 3; i >= 0; --i) v = (v << 8) | bytes[at + static_cast<std::size_t>(i)];
    ints.push_back(static_cast<std::int32_t>(v));
  }
  return ints;
}

// 2N words: every motor at 0° with its default torque, but for `angles` (motor → degrees) at full torque.
std::vector<std::int32_t> Pose(const std::map<int, double>& angles) {
  std::vector<std::int32_t> words(2 * kMotors, kDefaultTorque);
  for (int m = 0; m < kMotors; ++m) words[static_cast<std::size_t>(m)] = kCentre;
  for (const auto& [motor, degrees] : angles) {
    words[static_cast<std::size_t>(motor)] = AngleWord(degrees);
    words[static_cast<std::size_t>(kMotors + motor)] = kFullTorque;
  }
  return words;
}

// Get-motors as the original answers it: the angle sensors' words, each within `degrees` of `goals`' angle, then
// the torque words exactly as in `set`.
void ExpectSensed(const std::vector<std::int32_t>& words, const std::vector<std::int32_t>& goals,
                  const std::vector<std::int32_t>& set, double degrees) {
  ASSERT_EQ(words.size(), set.size());
  for (std::size_t m = 0; m < kMotors; ++m) EXPECT_NEAR(AngleOf(words[m]), AngleOf(goals[m]), degrees) << "motor " << m;
  EXPECT_EQ(std::vector<std::int32_t>(words.begin() + kMotors, words.end()),
            std::vector<std::int32_t>(set.begin() + kMotors, set.end()))
      << "the torque words as set";
}

using test_support::UdpPeer;

// An ODCP client of one server.
class OdcpClient {
 public:
  explicit OdcpClient(std::uint16_t port) : port_(port) {}
  bool Connect() {
    peer_.SendTo(port_, {5});
    const std::optional<Bytes> reply = peer_.Receive();
    return reply == Message(6, {15, 1});
  }
  void Set(const std::vector<std::int32_t>& words) { peer_.SendTo(port_, Message(100, words)); }
  std::vector<std::int32_t> Get() {
    peer_.SendTo(port_, {150});
    const std::optional<Bytes> reply = peer_.Receive();
    if (!reply || reply->empty() || reply->front() != 151) {
      ADD_FAILURE() << "no 151 reply";
      return {};
    }
    EXPECT_EQ(reply->size(), 1u + 4 * 2 * kMotors) << "no terminator byte";
    return Ints(*reply);
  }
  bool Disconnect() {
    peer_.SendTo(port_, {7});
    return peer_.Receive() == Bytes{8};
  }
  UdpPeer& peer() { return peer_; }
  std::uint16_t port() const { return port_; }

 private:
  std::uint16_t port_;
  UdpPeer peer_;
};

// Just enough OSP to control agents and step them with NaN inputs, which leave every input as ODCP set it.
class OspStepper {
 public:
  bool Handshake(std::uint16_t server_port) {
    peer_.SendTo(server_port, {5, 1, 1});
    const std::optional<Bytes> ack = peer_.Receive(milliseconds(5000), &handler_);
    return ack == Bytes{6, 1, 1, 120};
  }
  bool TakeControl(std::int32_t agent) {
    peer_.SendTo(handler_, Message(100, {agent}));
    const std::optional<Bytes> reply = peer_.Receive();
    return reply && reply->size() == 7 && (*reply)[0] == 101 && (*reply)[5] == 1;
  }
  // One step of every agent in `agents`; the raw outputs per agent.
  std::vector<std::vector<float>> Step(const std::vector<std::int32_t>& agents) {
    std::vector<std::int32_t> fields;
    for (std::int32_t agent : agents) {
      fields = {agent, 2 * kMotors};
      for (int i = 0; i < 2 * kMotors; ++i) fields.push_back(std::bit_cast<std::int32_t>(std::nanf("")));
      peer_.SendTo(handler_, Message(80, fields));
      const std::optional<Bytes> ack = peer_.Receive();
      EXPECT_TRUE(ack && ack->front() == 81);
    }
    std::vector<std::vector<float>> outputs;
    for (std::size_t a = 0; a < agents.size(); ++a) {
      const std::optional<Bytes> result = peer_.Receive();
      if (!result || result->front() != 85) {
        ADD_FAILURE() << "no step result";
        return outputs;
      }
      const std::vector<std::int32_t> ints = Ints(*result);
      EXPECT_EQ(ints[0], agents[a]);
      std::vector<float> values;
      for (std::size_t i = 0; i < static_cast<std::size_t>(ints[1]); ++i) {
        values.push_back(std::bit_cast<float>(ints[5 + i]));
      }
      outputs.push_back(values);
      peer_.SendTo(handler_, {86});
    }
    return outputs;
  }

 private:
  UdpPeer peer_;
  std::uint16_t handler_ = 0;
};

// "PREFIX NAME=127.0.0.1:PORT" → PORT; 0 when the line does not match.
std::uint16_t PortOf(const std::optional<std::string>& line, const std::string& prefix) {
  std::smatch match;
  if (!line || !std::regex_match(*line, match, std::regex(prefix + "=127\\.0\\.0\\.1:(\\d+)"))) return 0;
  return static_cast<std::uint16_t>(std::stoi(match[1]));
}

// An orcs-sim CSV log: the column names and the rows.
struct Log {
  std::vector<std::string> columns;       // from the "# columns: " line; the first is the time
  std::vector<std::vector<double>> rows;  // one per line that is not a comment
  std::size_t Column(const std::string& name) const {
    const auto it = std::find(columns.begin(), columns.end(), name);
    EXPECT_NE(it, columns.end()) << name;
    return static_cast<std::size_t>(it - columns.begin());
  }
};

std::vector<std::string> Split(const std::string& line) {
  std::vector<std::string> fields;
  std::stringstream stream(line);
  for (std::string field; std::getline(stream, field, ',');) fields.push_back(field);
  return fields;
}

Log ReadLog(const std::string& text) {
  Log log;
  std::stringstream stream(text);
  for (std::string line; std::getline(stream, line);) {
    if (line.rfind("# columns: ", 0) == 0) log.columns = Split(line.substr(11));
    if (line.empty() || line[0] == '#') continue;
    std::vector<double> row;
    for (const std::string& field : Split(line)) row.push_back(std::stod(field));
    log.rows.push_back(row);
  }
  return log;
}

class OdcpTest : public ::testing::Test {
 protected:
  test_support::TempDir dir_;
};

TEST_F(OdcpTest, OrcsOspSetsMotorWordsPerAgentAndTheAnglesFollow) {
  BackgroundProcess server({kBin + "orcs-osp", "-env", dir_.Write("two.xml", kTwoRobots), "-port", "0",
                            "-odcp_port", "0"});
  const std::uint16_t osp_port = PortOf(server.ReadLine(milliseconds(10000)), "orcs-osp osp");
  ASSERT_NE(osp_port, 0) << server.err();
  OdcpClient first(PortOf(server.ReadLine(milliseconds(5000)), "orcs-osp odcp Humanoid"));
  OdcpClient second(PortOf(server.ReadLine(milliseconds(5000)), "orcs-osp odcp SecondASeries"));
  ASSERT_NE(first.port(), 0);
  ASSERT_NE(second.port(), 0);
  ASSERT_NE(first.port(), second.port());

  ASSERT_TRUE(second.Connect());
  // Get-motors reports the angle sensors, as the original did (noise σ 0.19°): 0° and the default torque at
  // first; after a set-motors, still the sensors until the joints move, with the torques as set.
  ExpectSensed(second.Get(), Pose({}), Pose({}), 1.0);
  const std::vector<std::int32_t> pose = Pose({{kRightShoulderYaw, 45.0}, {kRightElbow, -30.0}});
  second.Set(pose);
  const std::vector<std::int32_t> before = second.Get();
  ExpectSensed(before, Pose({}), pose, 1.0);
  EXPECT_NE(before[kRightShoulderYaw], pose[kRightShoulderYaw]) << "the sensor, not the goal";

  OspStepper stepper;
  ASSERT_TRUE(stepper.Handshake(osp_port));
  ASSERT_TRUE(stepper.TakeControl(1));
  ASSERT_TRUE(stepper.TakeControl(2));
  std::vector<std::vector<float>> outputs;
  for (int step = 0; step < 100; ++step) outputs = stepper.Step({1, 2});  // 1 s
  ASSERT_EQ(outputs.size(), 2u);
  // Raw JointAngle outputs (degrees): the second robot's arm went where its words said; the first stayed.
  EXPECT_NEAR(outputs[1][kRightShoulderYaw], AngleOf(AngleWord(45.0)), 2.0);
  EXPECT_NEAR(outputs[1][kRightElbow], AngleOf(AngleWord(-30.0)), 2.0);
  EXPECT_NEAR(outputs[0][kRightShoulderYaw], 0.0, 2.0);
  EXPECT_NEAR(outputs[0][kRightElbow], 0.0, 2.0);
  ExpectSensed(second.Get(), pose, pose, 2.0);  // the sensors followed; NaN steps left the torques alone
  EXPECT_TRUE(second.Disconnect());
}

TEST_F(OdcpTest, BadOdcpDatagramsAreSurvived) {
  // The successor's get-motors (the goal words as set), so that the clamping of each word shows.
  const std::string goals = dir_.Write("goals.val", "/SimpleUdpMotorInterface/ReportGoalAngles=T\n");
  BackgroundProcess server({kBin + "orcs-osp", "-ival", goals, "-port", "0", "-odcp_port", "0"});
  const std::uint16_t osp_port = PortOf(server.ReadLine(milliseconds(10000)), "orcs-osp osp");
  OdcpClient client(PortOf(server.ReadLine(milliseconds(5000)), "orcs-osp odcp Humanoid"));
  ASSERT_NE(client.port(), 0) << server.err();
  std::vector<std::int32_t> too_few = Pose({});
  too_few.pop_back();
  const std::vector<Bytes> garbage = {
      {},                                 // empty
      {100, 1, 0},                        // set-motors cut short
      Message(100, too_few),              // one word too few
      Bytes(5000, 100),                   // oversized
      {0xff, 0xfe, 0xfd},                 // unknown command
      Message(100, std::vector<std::int32_t>(2 * kMotors + 1, 5)),  // one word too many
  };
  for (const Bytes& bytes : garbage) client.peer().SendTo(client.port(), bytes);
  EXPECT_FALSE(client.peer().Receive(milliseconds(200)).has_value()) << "ignored: no reply";
  EXPECT_EQ(client.Get(), Pose({})) << "nothing was applied";

  std::vector<std::int32_t> wild = Pose({});
  wild[0] = -1;
  wild[1] = 1024;
  wild[kMotors] = std::numeric_limits<std::int32_t>::min();
  wild[kMotors + 1] = std::numeric_limits<std::int32_t>::max();
  client.Set(wild);
  std::vector<std::int32_t> clamped = Pose({});
  clamped[0] = 0;
  clamped[1] = 1023;
  clamped[kMotors] = 0;
  clamped[kMotors + 1] = 1023;
  EXPECT_EQ(client.Get(), clamped) << "out-of-range words are clamped";
  EXPECT_TRUE(client.Connect()) << "still answering";
  OspStepper stepper;
  EXPECT_TRUE(stepper.Handshake(osp_port)) << "and so is OSP";
  EXPECT_EQ(server.Wait(milliseconds(0)), std::nullopt) << "still running";
}

TEST_F(OdcpTest, OrcsSimRealtimeServesOdcpWhileItRuns) {
  const std::string log = dir_.PathOf("realtime.csv");
  // The successor's get-motors: the goal words as set (ODCP's "report goal angles" switch in a value file).
  const std::string goals = dir_.Write("goals.val", "/SimpleUdpMotorInterface/ReportGoalAngles=T\n");
  BackgroundProcess sim({kBin + "orcs-sim", "--realtime", "-port", "0", "-val", goals, "--duration", "1.5", "--log",
                         "/Sim/Humanoid/Right/(ShoulderYaw|Elbow)/JointAngle", "--out", log});
  OdcpClient client(PortOf(sim.ReadLine(milliseconds(10000)), "orcs-sim odcp Humanoid"));
  ASSERT_NE(client.port(), 0) << sim.err();
  ASSERT_TRUE(client.Connect());
  const std::vector<std::int32_t> pose = Pose({{kRightShoulderYaw, 45.0}, {kRightElbow, -30.0}});
  client.Set(pose);
  EXPECT_EQ(client.Get(), pose) << "the goal words as set";
  const std::optional<ProcessResult> result = sim.Wait(milliseconds(30000));
  ASSERT_TRUE(result.has_value());
  EXPECT_EQ(result->exit_code, 0) << result->err;
  std::smatch wall;
  ASSERT_TRUE(std::regex_search(result->out, wall, std::regex("wall time ([0-9.]+) s"))) << result->out;
  EXPECT_GE(std::stod(wall[1]), 1.45) << "paced to the wall clock";
  const Log trace = ReadLog(dir_.Read(log));
  ASSERT_EQ(trace.rows.size(), 151u);
  const std::vector<double>& last = trace.rows.back();
  EXPECT_NEAR(last[trace.Column("/Sim/Humanoid/Right/ShoulderYaw/JointAngle")], AngleOf(AngleWord(45.0)), 2.0);
  EXPECT_NEAR(last[trace.Column("/Sim/Humanoid/Right/Elbow/JointAngle")], AngleOf(AngleWord(-30.0)), 2.0);
}

// The original's interactive simulator: ODCP served without wall-clock pacing, each step followed by
// /Simulation/Delay, running until stopped.
TEST_F(OdcpTest, OrcsSimWithAPortRunsUntilStoppedDelayedPerStep) {
  const std::string log = dir_.PathOf("until.csv");
  BackgroundProcess sim({kBin + "orcs-sim", "-port", "0", "-val", dir_.Write("delay.val", "/Simulation/Delay=5\n"),
                         "--log", "/Sim/Humanoid/Right/ShoulderYaw/JointAngle", "--out", log});
  OdcpClient client(PortOf(sim.ReadLine(milliseconds(10000)), "orcs-sim odcp Humanoid"));
  ASSERT_NE(client.port(), 0) << sim.err();
  ASSERT_TRUE(client.Connect());
  client.Set(Pose({{kRightShoulderYaw, 45.0}}));
  // The arm follows (read through get-motors' angle sensors), however long the machine takes: the run has no end.
  double angle = 0.0;
  for (int i = 0; i < 500 && angle < 40.0; ++i) {
    angle = AngleOf(client.Get()[kRightShoulderYaw]);
    if (angle < 40.0) std::this_thread::sleep_for(milliseconds(20));  // the robot moves in simulated time
  }
  EXPECT_GE(angle, 40.0) << "the arm reached its goal";
  EXPECT_EQ(sim.Wait(milliseconds(0)), std::nullopt) << "still running";
  sim.Signal(SIGINT);
  const std::optional<ProcessResult> result = sim.Wait(milliseconds(10000));
  ASSERT_TRUE(result.has_value());
  EXPECT_EQ(result->exit_code, 0) << result->err;
  EXPECT_THAT(result->err, ::testing::HasSubstr("running until stopped"));
  std::smatch summary;
  ASSERT_TRUE(std::regex_search(result->out, summary, std::regex("in ([0-9]+) steps, wall time ([0-9.]+) s")))
      << result->out;
  const double steps = std::stod(summary[1]);
  EXPECT_GE(std::stod(summary[2]), 0.9 * steps * 0.005) << "each step waited its 5 ms";
  EXPECT_EQ(ReadLog(dir_.Read(log)).rows.size(), static_cast<std::size_t>(steps) + 1) << "the log is complete";
}

// The motion a test "editor" sends: arm poses, one every 100 ms.
std::vector<std::int32_t> MotionPose(int k, int count) {
  const double phase = 2.0 * M_PI * k / count;
  return Pose({{kRightShoulderYaw, 50.0 * std::sin(phase)},
               {kLeftShoulderYaw, -40.0 * std::sin(phase)},
               {kRightElbow, -35.0 * (1.0 - std::cos(phase))},
               {kLeftElbow, 30.0 * (1.0 - std::cos(phase))}});
}

// A raw keyframe record written from the words and their times, straight from the spec.
std::string RecordOf(const std::vector<double>& times_ms, const std::vector<std::vector<std::int32_t>>& poses) {
  std::ostringstream out;
  out.precision(17);
  out << "# layout: raw\n";
  for (std::size_t k = 0; k < poses.size(); ++k) {
    out << times_ms[k];
    for (int m = 0; m < kMotors; ++m) {
      out << "," << AngleOf(poses[k][static_cast<std::size_t>(m)]) << ","
          << TorqueOf(poses[k][static_cast<std::size_t>(kMotors + m)]);
    }
    out << "\n";
  }
  return out.str();
}

// Replays a record into Humanoid for 2.2 s and returns every JointAngle at every step.
Log Replay(const std::string& record, const std::string& out) {
  const ProcessResult result = RunProcess({kBin + "orcs-sim", "-play", "Humanoid", record, "--duration", "2.2",
                                           "--log", ".*/JointAngle", "--out", out});
  EXPECT_EQ(result.exit_code, 0) << result.err;
  std::ifstream file(out);
  std::stringstream text;
  text << file.rdbuf();
  return ReadLog(text.str());
}

TEST_F(OdcpTest, TheSniffersRecordReplaysTheMotionThatWasSent) {
  const std::string sniffed = dir_.PathOf("sniffed.csv");
  BackgroundProcess sniffer({kBin + "orcs-sniffer", sniffed, "-port", "0"});
  OdcpClient editor(PortOf(sniffer.ReadLine(milliseconds(10000)), "orcs-sniffer odcp"));
  ASSERT_NE(editor.port(), 0) << sniffer.err();
  ASSERT_TRUE(editor.Connect());
  EXPECT_EQ(editor.Get(), Pose({})) << "answers get-motors like a server: the A-Series defaults";

  // Commands at 0 ms and then 3 ms past every 100 ms, the editor's own pace. How long a datagram takes to be
  // read depends on the machine's load (up to ~15 ms seen while other tests ran), so the record is checked
  // against the times the sniffer saw, and those against the times of sending only loosely.
  constexpr int kCommands = 20;
  std::vector<std::vector<std::int32_t>> poses;
  std::vector<double> sent_ms;
  Clock::time_point first = Clock::now();
  for (int k = 0; k < kCommands; ++k) {
    poses.push_back(MotionPose(k, kCommands));
    if (k > 0) std::this_thread::sleep_until(first + milliseconds(100 * k + 3));  // the editor's own pace
    const Clock::time_point now = Clock::now();
    if (k == 0) first = now;
    sent_ms.push_back(std::chrono::duration<double, std::milli>(now - first).count());
    editor.Set(poses.back());
  }
  EXPECT_EQ(editor.Get(), poses.back());
  ASSERT_TRUE(editor.Disconnect());
  const std::optional<ProcessResult> result = sniffer.Wait(milliseconds(10000));
  ASSERT_TRUE(result.has_value()) << "the disconnect ends the recording";
  ASSERT_EQ(result->exit_code, 0) << result->err;
  EXPECT_THAT(result->out, ::testing::HasSubstr("recorded 20 keyframes"));

  // The rows: one per command, at its time since the first, with the words' raw values.
  std::vector<std::vector<double>> rows;
  for (const std::vector<double>& row : ReadLog(dir_.Read(sniffed)).rows) rows.push_back(row);
  ASSERT_EQ(rows.size(), static_cast<std::size_t>(kCommands));
  EXPECT_EQ(rows[0][0], 0.0) << "times count from the first command, not from the connect";
  double latest = 0.0;
  std::vector<double> recorded_ms;
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const std::vector<double>& row = rows[k];
    ASSERT_EQ(row.size(), 1u + 2 * kMotors);
    EXPECT_NEAR(row[0], sent_ms[k], 50.0) << "row " << k << ": recorded at another time than it was sent";
    if (k > 0) {
      EXPECT_GT(row[0], recorded_ms.back()) << "row " << k << ": times must grow";
    }
    recorded_ms.push_back(row[0]);
    latest = std::max(latest, std::abs(row[0] - sent_ms[k]));
    for (std::size_t m = 0; m < kMotors; ++m) {
      EXPECT_NEAR(row[1 + 2 * m], AngleOf(poses[k][m]), 1e-9) << "row " << k << ", motor " << m;
      EXPECT_NEAR(row[2 + 2 * m], TorqueOf(poses[k][kMotors + m]), 1e-9) << "row " << k << ", motor " << m;
    }
  }

  // The replay of the sniffed record against the replay of what was sent, at the times it arrived.
  const Log replayed = Replay(sniffed, dir_.PathOf("replayed.csv"));
  const Log reference =
      Replay(dir_.Write("sent.csv", RecordOf(recorded_ms, poses)), dir_.PathOf("reference.csv"));
  ASSERT_EQ(replayed.columns, reference.columns);
  ASSERT_EQ(replayed.rows.size(), 221u);
  ASSERT_EQ(reference.rows.size(), 221u);
  double error = 0.0;
  for (std::size_t r = 0; r < replayed.rows.size(); ++r) {
    for (std::size_t c = 1; c < replayed.columns.size(); ++c) {
      error = std::max(error, std::abs(replayed.rows[r][c] - reference.rows[r][c]));
    }
  }
  EXPECT_LE(error, kSensorNoiseDegrees) << "the largest joint-angle difference, degrees";
  // The motion is real: the right arm swung out to about +50° and back past −40°.
  const std::size_t yaw = replayed.Column("/Sim/Humanoid/Right/ShoulderYaw/JointAngle");
  double high = -1e9;
  double low = 1e9;
  for (const std::vector<double>& row : replayed.rows) {
    high = std::max(high, row[yaw]);
    low = std::min(low, row[yaw]);
  }
  EXPECT_GT(high, 40.0);
  EXPECT_LT(low, -40.0);
  std::cout << "sniffed record vs motion sent: largest time difference " << latest
            << " ms, largest joint-angle difference in the replay " << error << " degrees over "
            << replayed.rows.size() << " steps\n";
}

TEST_F(OdcpTest, BadCommandLinesExitTwoWithOneLine) {
  const ProcessResult record_for_ever = RunProcess({kBin + "orcs-sim", "-port", "0", "--record", dir_.PathOf("r")});
  EXPECT_EQ(record_for_ever.exit_code, 2);
  EXPECT_THAT(record_for_ever.err, ::testing::HasSubstr("--record: needs --duration S with -port"));
  const ProcessResult bad_delay = RunProcess(
      {kBin + "orcs-sim", "-val", dir_.Write("bad.val", "/Simulation/Delay=-5\n"), "--duration", "0.1"});
  EXPECT_EQ(bad_delay.exit_code, 2);
  EXPECT_THAT(bad_delay.err, ::testing::HasSubstr("/Simulation/Delay: expected milliseconds between 0 and"));
  const ProcessResult no_file = RunProcess({kBin + "orcs-sniffer"});
  EXPECT_EQ(no_file.exit_code, 2);
  const ProcessResult bad_dir = RunProcess({kBin + "orcs-sniffer", dir_.PathOf("no/such/dir/x.csv"), "-port", "0"});
  EXPECT_EQ(bad_dir.exit_code, 2);
  EXPECT_THAT(bad_dir.err, ::testing::HasSubstr("x.csv"));
  // A port in use: the sniffer holds one, orcs-osp is asked for it.
  BackgroundProcess sniffer({kBin + "orcs-sniffer", dir_.PathOf("x.csv"), "-port", "0"});
  const std::uint16_t taken = PortOf(sniffer.ReadLine(milliseconds(10000)), "orcs-sniffer odcp");
  ASSERT_NE(taken, 0);
  const ProcessResult in_use =
      RunProcess({kBin + "orcs-osp", "-port", "0", "-odcp_port", std::to_string(taken)});
  EXPECT_EQ(in_use.exit_code, 2);
  EXPECT_THAT(in_use.err, ::testing::HasSubstr("-odcp_port"));
  EXPECT_EQ(std::count(in_use.err.begin(), in_use.err.end(), '\n'), 1) << in_use.err;
}

}  // namespace
}  // namespace orcs
