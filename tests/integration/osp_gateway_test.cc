// orcs-osp driven over real UDP sockets on 127.0.0.1 by a client written from docs/spec/osp.md alone (its
// own encoding below; nothing of the server's code): the handshake, agent overview and info, exclusive control,
// lock-step stepping of two clients, values by id, an observed collision event, reset with a seed, silent
// clients, communication reset, and every kind of bad datagram.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <bit>
#include <csignal>
#include <cmath>
#include <cstring>
#include <optional>
#include <regex>

#include "model/evaluation/recording_reader.h"
#include "tests/support/background_process.h"
#include "tests/support/process.h"
#include "tests/support/temp_dir.h"
#include "tests/support/udp_peer.h"

namespace orcs {
namespace {

using std::chrono::milliseconds;
using test_support::BackgroundProcess;
using Bytes = std::vector<std::uint8_t>;

const std::string kBin = ORCS_BINARY_DIR "/bin/";
// Two robots a metre apart and a sphere dropped from 0.5 m beside them.
constexpr const char* kEnvironment = R"xml(<?xml version="1.0"?>
<ORCS version="1.0">
  <Environment>
    <object type="sphere" name="SecondSphere" position="(-0.6, 0.5, 0.3)" dimension="(0.05)"
            material="ABS" dynamic="true" mass="0.1"/>
  </Environment>
  <Agent>
    <ASeries name="Humanoid" position="(0, 0.001, 0)"/>
    <ASeries name="SecondASeries" position="(1, 0.001, 0)"/>
  </Agent>
</ORCS>
)xml";

// ---- The spec's encoding, written out again: byte, int32 LE, float32 bits LE, NUL string. ----
struct Message {
  Bytes bytes;
  Message& Byte(std::uint8_t b) { bytes.push_back(b); return *this; }
  Message& Int(std::int32_t v) {
    for (int i = 0; i < 4; ++i) bytes.push_back(static_cast<std::uint8_t>(static_cast<std::uint32_t>(v) >> (8 * i)));
    return *this;
  }
  Message& Float(float f) { return Int(std::bit_cast<std::int32_t>(f)); }
  Message& String(const std::string& s) {
    bytes.insert(bytes.end(), s.begin(), s.end());
    bytes.push_back(0);
    return *this;
  }
};

struct Parsed {
  Bytes bytes;
  std::size_t at = 0;
  std::uint8_t Byte() { return bytes.at(at++); }
  std::int32_t Int() {
    std::uint32_t v = 0;
    for (int i = 3; i >= 0; --i) v = (v << 8) | bytes.at(at + static_cast<std::size_t>(i));
    at += 4;
    return static_cast<std::int32_t>(v);
  }
  float Float() { return std::bit_cast<float>(Int()); }
  std::string String() {
    std::string s;
    while (bytes.at(at) != 0) s.push_back(static_cast<char>(bytes[at++]));
    ++at;
    return s;
  }
  bool EndsWith120() const { return !bytes.empty() && bytes.back() == 120; }
};

// A client: one UDP socket; after the handshake it talks to the handler port.
class OspClient {
 public:
  void SendTo(std::uint16_t port, const Bytes& bytes) { socket_.SendTo(port, bytes); }
  void Send(const Message& message) { SendTo(handler_port_, message.bytes); }
  // The next datagram within `timeout` (and the port it came from).
  std::optional<Parsed> Receive(milliseconds timeout = milliseconds(5000), std::uint16_t* from_port = nullptr) {
    std::optional<Bytes> bytes = socket_.Receive(timeout, from_port);
    if (!bytes) return std::nullopt;
    return Parsed{std::move(*bytes)};
  }
  // The next datagram, which must start with `code` and end with 120.
  Parsed Expect(std::uint8_t code) {
    std::optional<Parsed> reply = Receive();
    if (!reply) {
      ADD_FAILURE() << "no reply, expected " << int{code};
      return Parsed{Bytes{0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0}};
    }
    EXPECT_EQ(reply->Byte(), code);
    EXPECT_TRUE(reply->EndsWith120());
    return *reply;
  }
  bool Handshake(std::uint16_t server_port) {
    SendTo(server_port, Message().Byte(5).Byte(1).Byte(1).bytes);
    std::uint16_t from = 0;
    std::optional<Parsed> ack = Receive(milliseconds(5000), &from);
    if (!ack || ack->bytes != Bytes{6, 1, 1, 120} || from == server_port) return false;
    handler_port_ = from;
    return true;
  }

  std::int32_t ValueId(const std::string& path) {
    Send(Message().Byte(40).String(path));
    Parsed count = Expect(41);
    const std::int32_t n = count.Int();
    std::int32_t id = 0;
    for (std::int32_t i = 0; i < n; ++i) {
      Parsed entry = Expect(43);
      EXPECT_EQ(entry.Int(), i);
      id = entry.Int();
      entry.String();
      EXPECT_EQ(entry.String(), path);
      Send(Message().Byte(42));
    }
    EXPECT_EQ(n, 1) << path;
    return id;
  }
  std::string Get(std::int32_t id) {
    Send(Message().Byte(50).Int(id));
    Parsed reply = Expect(51);
    EXPECT_EQ(reply.Int(), id);
    return reply.String();
  }
  std::uint8_t Set(std::int32_t id, const std::string& value) {
    Send(Message().Byte(52).Int(id).String(value));
    Parsed reply = Expect(53);
    EXPECT_EQ(reply.Int(), id);
    return reply.Byte();
  }
  bool TakeControl(std::int32_t agent) {
    Send(Message().Byte(100).Int(agent));
    Parsed reply = Expect(101);
    EXPECT_EQ(reply.Int(), agent);
    return reply.Byte() == 1;
  }
  void SendStep(std::int32_t agent, const std::vector<float>& inputs) {
    Message message;
    message.Byte(80).Int(agent).Int(static_cast<std::int32_t>(inputs.size()));
    for (float f : inputs) message.Float(f);
    Send(message);
    Parsed ack = Expect(81);
    EXPECT_EQ(ack.Int(), agent);
  }
  struct StepResult {
    std::vector<float> outputs;
    std::vector<std::int32_t> events;
    std::vector<std::pair<std::int32_t, std::string>> values;  // observed values: id, printed value
    std::size_t bytes = 0;                                      // the datagram's size
  };
  StepResult ReceiveStepResult(std::int32_t agent) {
    Parsed reply = Expect(85);
    StepResult result;
    result.bytes = reply.bytes.size();
    EXPECT_EQ(reply.Int(), agent);
    const std::int32_t outputs = reply.Int();
    EXPECT_EQ(reply.Int(), 0);  // no info values
    const std::int32_t events = reply.Int();
    const std::int32_t values = reply.Int();
    for (std::int32_t i = 0; i < outputs; ++i) result.outputs.push_back(reply.Float());
    for (std::int32_t i = 0; i < events; ++i) result.events.push_back(reply.Int());
    for (std::int32_t i = 0; i < values; ++i) {
      const std::int32_t id = reply.Int();
      result.values.emplace_back(id, reply.String());
    }
    EXPECT_EQ(reply.at + 1, reply.bytes.size()) << "nothing between the last field and the 120";
    Send(Message().Byte(86));
    return result;
  }
  // The ids of every value whose path matches `pattern` (40/41/43).
  std::vector<std::int32_t> ValueIds(const std::string& pattern) {
    Send(Message().Byte(40).String(pattern));
    const std::int32_t n = Expect(41).Int();
    std::vector<std::int32_t> ids;
    for (std::int32_t i = 0; i < n; ++i) {
      Parsed entry = Expect(43);
      entry.Int();
      ids.push_back(entry.Int());
      Send(Message().Byte(42));
    }
    return ids;
  }
  void Observe(const std::vector<std::int32_t>& ids) {
    Message message;
    message.Byte(54).Int(static_cast<std::int32_t>(ids.size()));
    for (std::int32_t id : ids) message.Int(id);
    Send(message);
    EXPECT_EQ(Expect(55).Int(), static_cast<std::int32_t>(ids.size()));
  }
  void Reset(std::int32_t seed) {
    Send(Message().Byte(70).Int(seed));
    Expect(71);
  }

  std::uint16_t handler_port() const { return handler_port_; }

 private:
  test_support::UdpPeer socket_;
  std::uint16_t handler_port_ = 0;
};

// 42 normalised inputs: every motor at angle n·150° with full torque.
std::vector<float> Inputs(float angle) {
  std::vector<float> inputs;
  for (int motor = 0; motor < 21; ++motor) {
    inputs.push_back(angle);
    inputs.push_back(1.0f);
  }
  return inputs;
}

class OspGatewayTest : public ::testing::Test {
 protected:
  void Start(std::vector<std::string> extra = {}) {
    std::vector<std::string> argv = {kBin + "orcs-osp", "-env", dir_.Write("two.xml", kEnvironment), "-port", "0",
                                     "-odcp_port", "0"};
    argv.insert(argv.end(), extra.begin(), extra.end());
    server_ = std::make_unique<BackgroundProcess>(argv);
    const std::optional<std::string> line = server_->ReadLine(milliseconds(10000));
    ASSERT_TRUE(line.has_value()) << server_->err();
    std::smatch match;
    const std::regex pattern("orcs-(osp|view) osp=127\\.0\\.0\\.1:(\\d+)");  // orcs-view: with -gui
    ASSERT_TRUE(std::regex_match(*line, match, pattern)) << *line;
    port_ = static_cast<std::uint16_t>(std::stoi(match[2]));
  }
  test_support::TempDir dir_;
  std::unique_ptr<BackgroundProcess> server_;
  std::uint16_t port_ = 0;
};

TEST_F(OspGatewayTest, HandshakeOverviewAndInfoFollowTheSpec) {
  Start();
  OspClient client;
  ASSERT_TRUE(client.Handshake(port_));
  client.Send(Message().Byte(90));
  Parsed count = client.Expect(91);
  ASSERT_EQ(count.Int(), 2);
  std::vector<std::string> names;
  for (int i = 0; i < 2; ++i) {
    Parsed entry = client.Expect(92);
    EXPECT_EQ(entry.Int(), i);
    EXPECT_EQ(entry.Int(), i + 1);
    EXPECT_EQ(entry.String(), "Agent");
    EXPECT_EQ(entry.Byte(), 1);  // available
    names.push_back(entry.String());
    client.Send(Message().Byte(93));
  }
  EXPECT_EQ(names, (std::vector<std::string>{"Humanoid", "SecondASeries"}));

  client.Send(Message().Byte(95).Int(2));
  Parsed info = client.Expect(96);
  EXPECT_EQ(info.Int(), 2);
  EXPECT_EQ(info.Int(), 42);
  EXPECT_EQ(info.Int(), 37);
  EXPECT_EQ(info.Int(), 0);
  EXPECT_EQ(info.String(), "SecondASeries");
  std::vector<std::string> values;
  std::vector<std::pair<float, float>> ranges;
  for (int i = 0; i < 79; ++i) {
    Parsed value = client.Expect(98);
    EXPECT_EQ(value.Int(), i);
    const float low = value.Float();
    const float high = value.Float();
    ranges.emplace_back(low, high);
    values.push_back(value.String());
    client.Send(Message().Byte(97));
  }
  EXPECT_EQ(values[0], "/Waist/DesiredAngle");  // motor order of spec/aseries.md §4c
  EXPECT_EQ(values[1], "/Waist/DesiredTorque");
  EXPECT_EQ(ranges[1], std::make_pair(0.0f, 1.0f));
  EXPECT_EQ(values[2], "/Right/ShoulderYaw/DesiredAngle");
  EXPECT_EQ(values[42], "/Waist/JointAngle");
  EXPECT_EQ(ranges[42], std::make_pair(-1.0f, 1.0f));
  EXPECT_EQ(values[63], "/ABFR/AccelAxis1");
  EXPECT_EQ(values[78], "/ABAL/AccelAxis2");

  client.Send(Message().Byte(95).Int(7));  // unknown agent: all zero
  Parsed unknown = client.Expect(96);
  EXPECT_EQ(unknown.Int(), 0);
  EXPECT_EQ(unknown.Int(), 0);

  client.Send(Message().Byte(7));
  client.Expect(8);
}

TEST_F(OspGatewayTest, TwoClientsStepTwoAgentsInLockStep) {
  Start();
  OspClient a;
  OspClient b;
  ASSERT_TRUE(a.Handshake(port_));
  ASSERT_TRUE(b.Handshake(port_));
  ASSERT_TRUE(a.TakeControl(1));
  ASSERT_TRUE(b.TakeControl(2));
  EXPECT_FALSE(b.TakeControl(1)) << "an agent has one controlling client";
  const std::int32_t time_id = a.ValueId("/Simulation/CurrentStep");
  for (int step = 1; step <= 5; ++step) {
    a.SendStep(1, Inputs(0.1f));
    EXPECT_FALSE(a.Receive(milliseconds(100)).has_value()) << "no step before every controller has sent its inputs";
    b.SendStep(2, Inputs(-0.1f));
    const OspClient::StepResult ra = a.ReceiveStepResult(1);
    const OspClient::StepResult rb = b.ReceiveStepResult(2);
    EXPECT_EQ(ra.outputs.size(), 37u);
    EXPECT_EQ(rb.outputs.size(), 37u);
    EXPECT_EQ(a.Get(time_id), std::to_string(step));
  }
  // Raw outputs in degrees: the commanded +15° and −15° turn the right shoulders (output 1) apart.
  for (int step = 0; step < 30; ++step) {
    a.SendStep(1, Inputs(0.1f));
    b.SendStep(2, Inputs(-0.1f));
    const float angle_a = a.ReceiveStepResult(1).outputs[1];
    const float angle_b = b.ReceiveStepResult(2).outputs[1];
    if (step == 29) {
      EXPECT_GT(angle_a, 5.0f);
      EXPECT_LT(angle_b, -5.0f);
    }
  }
}

TEST_F(OspGatewayTest, ValuesAreReadAndSetById) {
  Start();
  OspClient client;
  ASSERT_TRUE(client.Handshake(port_));
  const std::int32_t id = client.ValueId("/AngularMotor/PID/Proportional");
  EXPECT_GT(id, 0);
  EXPECT_EQ(client.Set(id, "12.5"), 1);
  EXPECT_EQ(client.Get(id), "12.5");
  EXPECT_EQ(client.Set(id, "abc"), 0);
  EXPECT_EQ(client.Get(id), "12.5");
  EXPECT_EQ(client.Set(999999, "1"), 2);
  client.Send(Message().Byte(50).Int(999999));
  Parsed unknown = client.Expect(51);
  EXPECT_EQ(unknown.Int(), -1);
  EXPECT_EQ(unknown.String(), "");
  client.Send(Message().Byte(54).Int(2).Int(id).Int(999999));
  Parsed observed = client.Expect(55);
  EXPECT_EQ(observed.Int(), 2);
  EXPECT_EQ(observed.Int(), id);
  EXPECT_EQ(observed.Int(), 0);
}

// Structure values (issue 48): a sphere's radius written over OSP applies at the next reset — the physics then
// rests it on its new radius, read back through its published position — and a robot body's mass that cannot
// be built is refused (status 0), an acceptable one taken (status 1).
TEST_F(OspGatewayTest, AStructureValueWrittenOverOspChangesTheWorldAtTheReset) {
  Start();
  OspClient client;
  ASSERT_TRUE(client.Handshake(port_));
  ASSERT_TRUE(client.TakeControl(1));
  const std::int32_t radius = client.ValueId("/Sim/SecondSphere/Radius");
  const std::int32_t position = client.ValueId("/Sim/SecondSphere/Position");
  const auto height_after_one_second = [&] {
    for (int step = 0; step < 100; ++step) {
      client.SendStep(1, Inputs(0.0f));
      client.ReceiveStepResult(1);
    }
    const std::string text = client.Get(position);  // "(x,y,z)"
    return std::stod(text.substr(text.find(',') + 1));
  };
  EXPECT_EQ(client.Set(radius, "0.15"), 1);
  EXPECT_NEAR(height_after_one_second(), 0.05, 0.005) << "the running world keeps its sphere until the reset";
  client.Reset(0);
  client.Expect(75);
  client.Send(Message().Byte(76));
  EXPECT_NEAR(height_after_one_second(), 0.15, 0.005) << "after the reset the sphere has its new radius";

  const std::int32_t foot = client.ValueId("/Sim/Humanoid/Right/Foot/Mass");
  EXPECT_GT(foot, 0);
  EXPECT_EQ(client.Set(foot, "0"), 0);
  EXPECT_EQ(client.Set(foot, "0.2"), 1);
  EXPECT_EQ(client.Get(foot), "0.2");

  // Crossed stops cannot be built: the reset is answered, the gateway logs why and steps on with its world.
  const std::int32_t max = client.ValueId("/Sim/Humanoid/Right/Knee/MaxAngle");
  const double above = std::stod(client.Get(max)) + 1.0;
  EXPECT_EQ(client.Set(client.ValueId("/Sim/Humanoid/Right/Knee/MinAngle"), std::to_string(above)), 1);
  client.Reset(0);
  client.Expect(75);
  client.Send(Message().Byte(76));
  EXPECT_NEAR(height_after_one_second(), 0.15, 0.005) << "stepping on";
  EXPECT_THAT(server_->err(), ::testing::HasSubstr("reset refused, the world runs on unchanged: /Sim/Humanoid/Right/Knee/MinAngle"));
}

TEST_F(OspGatewayTest, AnObservedCollisionEventShowsUpInTheStepReply) {
  Start();
  OspClient client;
  ASSERT_TRUE(client.Handshake(port_));
  client.Send(Message().Byte(20).String("/Sim/SecondSphere/Collision"));
  Parsed reply = client.Expect(21);
  const std::int32_t event = reply.Int();
  ASSERT_GT(event, 0);
  client.Send(Message().Byte(20).String("/No/Such/Event"));
  EXPECT_EQ(client.Expect(21).Int(), 0);
  client.Send(Message().Byte(30).Int(event));
  EXPECT_EQ(client.Expect(31).Int(), event);
  ASSERT_TRUE(client.TakeControl(1));
  int first_step_with_event = -1;
  for (int step = 1; step <= 100 && first_step_with_event < 0; ++step) {  // the sphere falls 0.45 m: ~0.3 s
    client.SendStep(1, Inputs(0.0f));
    const OspClient::StepResult result = client.ReceiveStepResult(1);
    if (!result.events.empty()) {
      EXPECT_EQ(result.events, std::vector<std::int32_t>{event});
      first_step_with_event = step;
    }
  }
  EXPECT_GT(first_step_with_event, 20);
  EXPECT_LT(first_step_with_event, 40);
}

// The original reported observed values after each step; the successor sends a count of 0 and clients poll
// with 50. orcs sends them in the step reply (85) unless /UDPCommunication/ObservedValuesInStepReply is false.
TEST_F(OspGatewayTest, ObservedValuesArriveWithEveryStepUnlessTheSuccessorsSwitchIsSet) {
  Start();
  OspClient client;
  ASSERT_TRUE(client.Handshake(port_));
  const std::int32_t angle = client.ValueId("/Sim/Humanoid/Right/ShoulderYaw/JointAngle");
  const std::int32_t time = client.ValueId("/Simulation/CurrentSimulationTime");
  ASSERT_GT(angle, 0);
  ASSERT_GT(time, 0);
  client.Observe({time, angle});
  ASSERT_TRUE(client.TakeControl(1));
  constexpr std::size_t kRightShoulderYawOutput = 1;  // outputs: the 21 JointAngles in motor order first
  for (int step = 1; step <= 20; ++step) {
    client.SendStep(1, Inputs(0.2f));  // 30°
    const OspClient::StepResult result = client.ReceiveStepResult(1);
    ASSERT_EQ(result.values.size(), 2u) << "step " << step;
    ASSERT_LT(time, angle);
    EXPECT_EQ(result.values[0].first, time) << "in id order";
    EXPECT_EQ(result.values[1].first, angle);
    EXPECT_NEAR(std::stod(result.values[0].second), 0.01 * step, 1e-9) << "the value after this step";
    EXPECT_EQ(result.values[0].second, client.Get(time)) << "the value as 50 reads it";
    EXPECT_NEAR(std::stod(result.values[1].second), result.outputs[kRightShoulderYawOutput], 1e-4)
        << "the value after this step, as its output";
  }
  EXPECT_EQ(client.Set(client.ValueId("/UDPCommunication/ObservedValuesInStepReply"), "F"), 1);
  client.SendStep(1, Inputs(0.2f));
  EXPECT_TRUE(client.ReceiveStepResult(1).values.empty()) << "the successor's count of 0";
}

TEST_F(OspGatewayTest, ObservedValuesBeyondOneDatagramAreLeftToPollingAndSaidOnce) {
  Start();
  OspClient client;
  ASSERT_TRUE(client.Handshake(port_));
  const std::vector<std::int32_t> ids = client.ValueIds("/Sim/Humanoid/.*/(JointAngle|DesiredAngle|DesiredTorque)");
  ASSERT_EQ(ids.size(), 63u);
  client.Observe(ids);
  ASSERT_TRUE(client.TakeControl(1));
  std::size_t sent = 0;
  for (int step = 0; step < 3; ++step) {
    client.SendStep(1, Inputs(0.1f));
    const OspClient::StepResult result = client.ReceiveStepResult(1);
    EXPECT_LE(result.bytes, 1024u);
    EXPECT_GT(result.values.size(), 10u);
    EXPECT_LT(result.values.size(), ids.size()) << "63 values do not fit one datagram";
    for (std::size_t i = 0; i < result.values.size(); ++i) EXPECT_EQ(result.values[i].first, ids[i]) << "the first ones";
    if (step == 0) sent = result.values.size();  // the log speaks of the first overflowing reply
  }
  server_->Signal(SIGTERM);
  const std::optional<test_support::ProcessResult> result = server_->Wait(milliseconds(10000));
  ASSERT_TRUE(result.has_value());
  const std::string said = "observes more values than a step reply carries; the first " + std::to_string(sent) +
                           " of 63 are sent, read the others with 50";
  EXPECT_THAT(result->err, ::testing::HasSubstr(said));
  EXPECT_EQ(result->err.find(said), result->err.rfind(said)) << "said once";
}

// The original's -play in the gateway: a keyframe record drives one robot in simulated time, which advances as the
// clients step another; a reset starts the record again.
TEST_F(OspGatewayTest, PlayDrivesARobotInSimulatedTimeAsTheClientsStepAndStartsAgainAtAReset) {
  const auto row = [](int ms, double degrees) {
    std::string line = std::to_string(ms);
    for (int motor = 0; motor < 21; ++motor) line += motor == 1 ? "," + std::to_string(degrees) + ",1" : ",0,0.586810005";
    return line + "\n";
  };
  const std::string record = dir_.Write("raise.csv", "# layout: raw\n" + row(0, 45.0) + row(500, 0.0));
  Start({"-play", "SecondASeries", record});
  OspClient client;
  ASSERT_TRUE(client.Handshake(port_));
  const std::int32_t played = client.ValueId("/Sim/SecondASeries/Right/ShoulderYaw/JointAngle");
  client.Observe({played});
  ASSERT_TRUE(client.TakeControl(1));
  const auto step_to = [&](int steps) {
    OspClient::StepResult result;
    for (int i = 0; i < steps; ++i) {
      client.SendStep(1, Inputs(0.0f));
      result = client.ReceiveStepResult(1);
    }
    EXPECT_EQ(result.values.size(), 1u);
    EXPECT_NEAR(result.outputs.at(1), 0.0, 2.0) << "the client's robot keeps its arm down";
    return result.values.empty() ? 0.0 : std::stod(result.values[0].second);
  };
  EXPECT_NEAR(step_to(40), 45.0, 2.0) << "at 0.4 s the record's first row has raised the arm";
  EXPECT_NEAR(step_to(60), 0.0, 2.0) << "at 1.0 s its row at 500 ms has lowered it";
  client.Reset(1);
  client.Expect(75);
  client.Send(Message().Byte(76));
  EXPECT_NEAR(step_to(40), 45.0, 2.0) << "after the reset the record plays from its start";
}

// --record DIR: the OSP-driven run, watched afterwards in orcs-view — one recording per episode (reset to reset),
// the last one written when the gateway stops.
TEST_F(OspGatewayTest, RecordWritesOneRecordingPerEpisodeThatTheViewerReads) {
  const std::string folder = dir_.PathOf("recorded");
  Start({"--record", folder});
  OspClient client;
  ASSERT_TRUE(client.Handshake(port_));
  ASSERT_TRUE(client.TakeControl(1));
  const auto steps = [&](int count) {
    for (int i = 0; i < count; ++i) {
      client.SendStep(1, Inputs(0.3f));
      client.ReceiveStepResult(1);
    }
  };
  steps(30);
  client.Reset(1);
  client.Expect(75);
  client.Send(Message().Byte(76));
  steps(10);
  server_->Signal(SIGTERM);
  const std::optional<test_support::ProcessResult> ended = server_->Wait(milliseconds(10000));
  ASSERT_TRUE(ended.has_value());
  EXPECT_EQ(ended->exit_code, 0) << ended->err;

  const evaluation::Recording first = evaluation::ReadRecording(folder + "/episode-0001.orcsrec");
  const evaluation::Recording second = evaluation::ReadRecording(folder + "/episode-0002.orcsrec");
  EXPECT_EQ(first.frame_count(), 31) << "frame 0 and the 30 steps before the reset";
  EXPECT_EQ(second.frame_count(), 11) << "frame 0 and the 10 steps after it";
  EXPECT_EQ(first.header.value("program", ""), "orcs-osp");
  const int knee = first.FindChannel("/Sim/Humanoid/Right/Knee/JointAngle");
  ASSERT_GE(knee, 0);
  EXPECT_GT(std::abs(first.value(30, knee) - first.value(0, knee)), 5.0f) << "the client's inputs moved the knee";
  EXPECT_THAT(ended->err, ::testing::HasSubstr("recorded episode 2: " + folder + "/episode-0002.orcsrec, 11 frames"));
}

// -gui hands the world to orcs-view (tests/browser/osp_gui.test.js drives that page); what it cannot pass on is
// refused with one line before anything starts.
TEST_F(OspGatewayTest, GuiRefusesWhatItCannotPassOnWithOneLine) {
  const std::string record = dir_.Write("r.csv", "# layout: raw\n");
  const test_support::ProcessResult played = test_support::RunProcess({kBin + "orcs-osp", "-gui", "-play", "Humanoid", record});
  EXPECT_EQ(played.exit_code, 2);
  EXPECT_THAT(played.err, ::testing::HasSubstr("-play: not with -gui yet"));
  const test_support::ProcessResult port = test_support::RunProcess({kBin + "orcs-osp", "--view-port", "0"});
  EXPECT_EQ(port.exit_code, 2);
  EXPECT_THAT(port.err, ::testing::HasSubstr("--view-port: only with -gui"));
}

// With noise on, a seeded reset and 20 steps of a sine on every motor: the outputs, as floats.
std::vector<float> SeededTrace(OspClient& client, std::int32_t seed) {
  client.Reset(seed);
  client.Expect(75);
  client.Send(Message().Byte(76));
  std::vector<float> angles;
  for (int step = 0; step < 20; ++step) {
    client.SendStep(1, Inputs(0.2f * std::sin(0.3f * static_cast<float>(step))));
    const std::vector<float> outputs = client.ReceiveStepResult(1).outputs;
    angles.insert(angles.end(), outputs.begin(), outputs.end());
  }
  return angles;
}

// orcs-osp -gui runs the same gateway inside orcs-view's live session: a client gets the same bits from it.
TEST_F(OspGatewayTest, TheGuiGatewayGivesTheSameBitsAsOrcsOsp) {
  const auto traced = [&](std::vector<std::string> extra) {
    Start(std::move(extra));
    OspClient client;
    EXPECT_TRUE(client.Handshake(port_));
    EXPECT_TRUE(client.TakeControl(1));
    EXPECT_EQ(client.Set(client.ValueId("/AngularMotor/IncludeNoise"), "T"), 1);
    std::vector<float> trace = SeededTrace(client, 7);
    server_->Signal(SIGTERM);
    EXPECT_TRUE(server_->Wait(milliseconds(10000)).has_value());
    return trace;
  };
  const std::vector<float> headless = traced({});
  const std::vector<float> watched = traced({"-gui", "--view-port", "0"});
  ASSERT_EQ(watched.size(), headless.size());
  EXPECT_EQ(std::memcmp(watched.data(), headless.data(), headless.size() * sizeof(float)), 0) << "bit for bit";
}

TEST_F(OspGatewayTest, ResetWithASeedGivesTheSameSensorTraceTwice) {
  Start();
  OspClient client;
  ASSERT_TRUE(client.Handshake(port_));
  ASSERT_TRUE(client.TakeControl(1));
  EXPECT_EQ(client.Set(client.ValueId("/AngularMotor/IncludeNoise"), "T"), 1);
  const auto trace = [&](std::int32_t seed) { return SeededTrace(client, seed); };
  const std::vector<float> first = trace(7);
  const std::vector<float> second = trace(7);
  EXPECT_EQ(std::memcmp(first.data(), second.data(), first.size() * sizeof(float)), 0) << "bit for bit";
  EXPECT_NE(trace(8), first) << "another seed, other noise";
}

TEST_F(OspGatewayTest, ResetWaitsForEveryControllingClient) {
  Start();
  OspClient a;
  OspClient b;
  ASSERT_TRUE(a.Handshake(port_));
  ASSERT_TRUE(b.Handshake(port_));
  ASSERT_TRUE(a.TakeControl(1));
  ASSERT_TRUE(b.TakeControl(2));
  a.Reset(3);
  EXPECT_FALSE(a.Receive(milliseconds(100)).has_value()) << "75 only once b has asked too";
  b.Reset(3);
  a.Expect(75);
  b.Expect(75);
}

TEST_F(OspGatewayTest, ASilentClientLosesItsAgents) {
  Start({"--client-timeout", "0.3"});
  OspClient silent;
  OspClient other;
  ASSERT_TRUE(silent.Handshake(port_));
  ASSERT_TRUE(silent.TakeControl(1));
  ASSERT_TRUE(other.Handshake(port_));
  ASSERT_TRUE(other.TakeControl(2));
  other.SendStep(2, Inputs(0.0f));  // waits for the silent client ...
  const std::optional<Parsed> result = other.Receive(milliseconds(3000));  // ... until it is dropped
  ASSERT_TRUE(result.has_value());
  EXPECT_EQ(result->bytes.front(), 85);
  EXPECT_TRUE(other.TakeControl(1)) << "the silent client's agent is free";
}

TEST_F(OspGatewayTest, ResetOfTheCommunicationDropsEveryClient) {
  Start();
  OspClient a;
  OspClient b;
  ASSERT_TRUE(a.Handshake(port_));
  ASSERT_TRUE(b.Handshake(port_));
  ASSERT_TRUE(b.TakeControl(1));
  a.Send(Message().Byte(10));
  a.Expect(11);
  b.Expect(71);
  b.Send(Message().Byte(90));
  EXPECT_FALSE(b.Receive(milliseconds(200)).has_value()) << "its handler is gone";
  OspClient c;
  ASSERT_TRUE(c.Handshake(port_));
  EXPECT_TRUE(c.TakeControl(1)) << "the server listens anew, every agent free";
}

TEST_F(OspGatewayTest, BadDatagramsAreIgnoredAndTheGatewayGoesOn) {
  Start();
  OspClient client;
  EXPECT_FALSE([&] {
    client.SendTo(port_, Message().Byte(5).Byte(2).Byte(0).bytes);  // another version: no reply
    return client.Receive(milliseconds(200)).has_value();
  }());
  ASSERT_TRUE(client.Handshake(port_));
  ASSERT_TRUE(client.TakeControl(1));
  const std::int32_t id = client.ValueId("/Simulation/TimeStepSize");
  const std::vector<Bytes> garbage = {
      {},                                                 // empty
      {50, 1, 0},                                         // truncated int
      Bytes(2000, 52),                                    // oversized
      {250, 1, 2, 3},                                     // unknown command
      Message().Byte(52).Int(id).Byte('x').bytes,         // a string without NUL
      Message().Byte(54).Int(1000000).bytes,              // a count beyond the datagram
      Message().Byte(80).Int(2).Int(42).bytes,            // a step for an agent it does not control
      Message().Byte(80).Int(1).Int(3).Float(0).Float(0).Float(0).bytes,  // wrong input count
      Message().Byte(100).Int(-5).bytes,                  // out-of-range id (answered: not ok)
  };
  for (const Bytes& bytes : garbage) client.SendTo(client.handler_port(), bytes);
  Parsed refused = client.Expect(101);
  EXPECT_EQ(refused.Int(), -5);
  EXPECT_EQ(refused.Byte(), 0);
  EXPECT_FALSE(client.Receive(milliseconds(100)).has_value()) << "the rest is ignored";
  EXPECT_EQ(client.Get(id), "0.01") << "the gateway still answers";
  // NaN inputs leave those inputs as they were; the step runs.
  std::vector<float> inputs = Inputs(0.0f);
  inputs[0] = std::nanf("");
  client.SendStep(1, inputs);
  EXPECT_EQ(client.ReceiveStepResult(1).outputs.size(), 37u);
  EXPECT_EQ(server_->Wait(milliseconds(0)), std::nullopt) << "still running";
}

}  // namespace
}  // namespace orcs
