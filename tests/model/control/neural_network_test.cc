#include "model/control/neural_network.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "model/control/controller_factory.h"
#include "model/control/sine_oscillator.h"
#include "tests/support/input_error_of.h"

namespace orcs::control {
namespace {

using test_support::InputErrorOf;
using ::testing::HasSubstr;

class ControllerTest : public ::testing::Test {
 protected:
  ControllerTest() {
    for (const char* motor : {"A", "B"}) {
      const std::string prefix = std::string("/Sim/R/") + motor + "/";
      values_.Add(prefix + "DesiredAngle", 0.0);
      values_.Add(prefix + "DesiredTorque", 0.5);
      values_.Add(prefix + "JointAngle", 0.0);
      values_.Add(prefix + "MinAngle", -150.0);
      values_.Add(prefix + "MaxAngle", 150.0);
    }
  }
  double Get(const std::string& path) { return values_.Get(path).as_double(); }
  VariableRepository values_;
  ControlTarget target_{"R", {"A", "B"}};
};

// in → h (recurrent) → A/DesiredAngle; free slots: h's bias, in→h, h→h.
const char* kTopology = R"({"type": "network",
  "inputs": [{"name": "in", "value": "A/JointAngle"}],
  "neurons": [{"name": "h", "bias": null}, {"name": "t", "bias": 0.5, "transfer": "sigmoid"}],
  "synapses": [{"from": "in", "to": "h", "weight": null}, {"from": "h", "to": "h", "weight": null}],
  "outputs": [{"neuron": "h", "value": "A/DesiredAngle"}, {"neuron": "t", "value": "A/DesiredTorque"}]})";

TEST_F(ControllerTest, NetworkStepMatchesHandComputation) {
  const nlohmann::json controller = nlohmann::json::parse(kTopology);
  EXPECT_EQ(CheckController(controller, target_, "s.json"), 3);
  auto network = MakeController(controller, {0.1, 2.0, 0.5}, target_, values_, "s.json");
  values_.Get("/Sim/R/A/JointAngle").Set(75.0);  // normalised 0.5
  network->Reset();
  network->Update(0.0);
  const double h1 = std::tanh(0.1 + 2.0 * 0.5 + 0.5 * 0.0);
  EXPECT_DOUBLE_EQ(Get("/Sim/R/A/DesiredAngle"), 150.0 * h1);
  // t = sigmoid(0.5) ∈ 0…1 is a normalised torque: raw = 2t − 1.
  EXPECT_DOUBLE_EQ(Get("/Sim/R/A/DesiredTorque"), 2.0 / (1.0 + std::exp(-0.5)) - 1.0);
  values_.Get("/Sim/R/A/JointAngle").Set(-150.0);  // normalised −1
  network->Update(0.01);
  const double h2 = std::tanh(0.1 + 2.0 * -1.0 + 0.5 * h1);  // recurrence uses the previous output
  EXPECT_DOUBLE_EQ(Get("/Sim/R/A/DesiredAngle"), 150.0 * h2);
}

TEST_F(ControllerTest, FullNetworkGenomeReplacesTheTopology) {
  const nlohmann::json full = nlohmann::json::parse(R"({"neurons": [{"name": "c", "bias": 0.2, "transfer": "linear"}],
      "outputs": [{"neuron": "c", "value": "B/DesiredAngle"}]})");
  auto network = MakeController(nlohmann::json::parse(kTopology), full, target_, values_, "s.json");
  network->Update(0.0);
  EXPECT_DOUBLE_EQ(Get("/Sim/R/B/DesiredAngle"), 0.2 * 150.0);
}

TEST_F(ControllerTest, BadGenomesAndNetworksAreNamed) {
  const nlohmann::json controller = nlohmann::json::parse(kTopology);
  EXPECT_EQ(InputErrorOf([&] { MakeController(controller, {1.0}, target_, values_, "s.json"); }),
            "s.json: field 'genome' expected 3 numbers, found an array of 1");
  EXPECT_EQ(InputErrorOf([&] { MakeController(controller, {1.0, "x", 2.0}, target_, values_, "s.json"); }),
            "s.json: field 'genome[1]' expected a number (genome values), found the string \"x\"");
  nlohmann::json with_slot = nlohmann::json::parse(R"({"neurons": [{"name": "c"}], "outputs": []})");
  EXPECT_THAT(InputErrorOf([&] { MakeController(controller, with_slot, target_, values_, "s.json"); }),
              HasSubstr("a full network has no genome slots"));
  nlohmann::json unknown = controller;
  unknown["synapses"][0]["from"] = "nobody";
  EXPECT_EQ(InputErrorOf([&] { CheckController(unknown, target_, "s.json"); }),
            "s.json: field 'controller.synapses[0].from' expected the name of an input or neuron, found 'nobody'");
  nlohmann::json bad_value = controller;
  bad_value["outputs"][0]["value"] = "C/DesiredAngle";
  EXPECT_EQ(InputErrorOf([&] { MakeController(bad_value, {1, 2, 3}, target_, values_, "s.json"); }),
            "s.json: controller: unknown repository value '/Sim/R/C/DesiredAngle'");
  EXPECT_THAT(InputErrorOf([&] { CheckController({{"type", "fuzzy"}}, target_, "s.json"); }),
              HasSubstr("field 'controller.type' expected \"network\", \"oscillator\", \"keyframes\", \"script\" or "
                        "\"plugin\""));
}

TEST_F(ControllerTest, OscillatorFollowsItsSine) {
  const nlohmann::json controller = {{"type", "oscillator"}, {"joints", {"B", "A"}}, {"torque", 1.0}};
  EXPECT_EQ(CheckController(controller, target_, "s.json"), 8);
  auto oscillator = MakeController(controller, {30, 0.5, 0, 10, 20, 1, M_PI / 2, 0}, target_, values_, "s.json");
  oscillator->Reset();
  EXPECT_EQ(Get("/Sim/R/A/DesiredTorque"), 1.0);
  oscillator->Update(0.5);  // B: 10 + 30·sin(π/2) = 40; A: 20·sin(π + π/2) = −20
  EXPECT_NEAR(Get("/Sim/R/B/DesiredAngle"), 40.0, 1e-12);
  EXPECT_NEAR(Get("/Sim/R/A/DesiredAngle"), -20.0, 1e-12);
  EXPECT_THAT(InputErrorOf([&] {
                CheckController({{"type", "oscillator"}, {"joints", {"Knee"}}}, target_, "s.json");
              }),
              HasSubstr("field 'controller.joints[0]' expected a motor of agent 'R'"));
}

}  // namespace
}  // namespace orcs::control
