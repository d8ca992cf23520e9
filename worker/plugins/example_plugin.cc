// The example plug-in (docs/extending.md, "Plug-ins"): built by the project's CMake as build/plugins/libexample.so,
// loaded by `orcs-worker --plugins build/plugins`. It uses nothing of orcs but model/script/plugin_api.h, as a
// plug-in built outside the project would:
//   g++ -std=c++20 -O2 -shared -fPIC -I<orcs source> my_plugin.cc -o libmine.so
//
//   example/mean_height   fitness term: the mean height of a body over the run, m (params: {"body": "Middle/Head"})
//   example/sine          controller: every listed motor at amplitude · sin(2π · frequency · t) degrees
//                         (params: {"motors": ["Right/HipPitch", ...]}; genome: amplitude (deg), frequency (Hz))
//   example/pd            motor model: a proportional servo — target rate gain · (desired − angle), at most
//                         max_velocity, with at most max_torque (params: {"gain": 1/s, "max_velocity": rad/s,
//                         "max_torque": N·m}; defaults 20, 5.8, 1.5)
#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <numbers>
#include <stdexcept>

#include "model/script/plugin_api.h"

namespace {

using orcs::plugin::SimulationView;

nlohmann::json Params(const std::string& text) {
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& error) {
    throw std::invalid_argument(error.what());
  }
}

class MeanHeight : public orcs::plugin::FitnessTerm {
 public:
  explicit MeanHeight(std::string body) : body_name_(std::move(body)) {}
  void Start(const SimulationView& view) override {
    body_ = view.body(body_name_);
    if (body_ < 0) throw std::invalid_argument("example/mean_height: no body '" + body_name_ + "'");
    sum_ = 0.0;
    steps_ = 0;
  }
  void Sample(const SimulationView& view, double) override {
    double xyz[3];
    view.position(body_, xyz);
    sum_ += xyz[1];
    ++steps_;
  }
  double Value() const override { return steps_ == 0 ? 0.0 : sum_ / static_cast<double>(steps_); }

 private:
  std::string body_name_;
  int body_ = -1;
  double sum_ = 0.0;
  long steps_ = 0;
};

class Sine : public orcs::plugin::Controller {
 public:
  Sine(std::vector<std::string> motors, double amplitude, double frequency)
      : names_(std::move(motors)), amplitude_(amplitude), frequency_(frequency) {}
  void Reset(const SimulationView& view) override {
    motors_.clear();
    for (const std::string& name : names_) {
      for (int m = 0; m < view.motor_count(); ++m) {
        if (view.motor_name(m) == name) motors_.push_back(m);
      }
    }
  }
  void Update(const SimulationView&, orcs::plugin::MotorCommands& commands, double time) override {
    const double angle = amplitude_ * std::sin(2 * std::numbers::pi * frequency_ * time);
    for (int motor : motors_) commands.set_angle(motor, angle);
  }

 private:
  std::vector<std::string> names_;
  std::vector<int> motors_;
  double amplitude_, frequency_;
};

class Pd : public orcs::plugin::MotorModel {
 public:
  Pd(double gain, double max_velocity, double max_torque)
      : gain_(gain), max_velocity_(max_velocity), max_torque_(max_torque) {}
  void Reset(double) override {}
  orcs::plugin::MotorOutput Update(const orcs::plugin::MotorInput& input) override {
    const double error = input.desired_angle * std::numbers::pi / 180.0 - input.angle;
    return {std::clamp(gain_ * error, -max_velocity_, max_velocity_), max_torque_, 0.0};
  }

 private:
  double gain_, max_velocity_, max_torque_;
};

}  // namespace

extern "C" int orcs_plugin_api_version() { return orcs::plugin::kApiVersion; }

extern "C" void orcs_plugin_register(orcs::plugin::Registrar& registrar) {
  registrar.AddFitnessTerm("mean_height", [](const std::string& params) {
    return std::make_unique<MeanHeight>(Params(params).value("body", "Middle/Head"));
  });
  registrar.AddController("sine", [](const std::string& params, const std::vector<double>& genome) {
    if (genome.size() != 2) throw std::invalid_argument("example/sine: a genome of 2 numbers (amplitude, frequency)");
    const nlohmann::json parsed = Params(params);
    if (!parsed.contains("motors") || !parsed["motors"].is_array()) {
      throw std::invalid_argument("example/sine: params.motors, a list of motor names");
    }
    return std::make_unique<Sine>(parsed["motors"].get<std::vector<std::string>>(), genome[0], genome[1]);
  });
  registrar.AddMotorModel("pd", [](const std::string& params, const std::string&) {
    const nlohmann::json parsed = Params(params);
    const double gain = parsed.value("gain", 20.0), velocity = parsed.value("max_velocity", 5.8),
                 torque = parsed.value("max_torque", 1.5);
    if (!(gain >= 0 && velocity >= 0 && torque >= 0)) {
      throw std::invalid_argument("example/pd: gain, max_velocity and max_torque at least 0");
    }
    return std::make_unique<Pd>(gain, velocity, torque);
  });
}
