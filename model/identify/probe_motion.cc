#include "model/identify/probe_motion.h"

#include <algorithm>
#include <cmath>

#include "model/aseries/value_range.h"
#include "model/core/error.h"
#include "model/core/text.h"

namespace orcs::identify {
namespace {

// Builds one motor's commands row by row, one row per rig step, from a few moves.
class Pattern {
 public:
  Pattern(double step, double lower, double upper) : step_(step), lower_(lower), upper_(upper) {}

  // Holds the current goal for `seconds`.
  Pattern& Hold(double seconds) { return Ramp(angle_, seconds); }
  // Moves the goal to `angle` at `speed` degrees per second.
  Pattern& RampAt(double angle, double speed) { return Ramp(angle, std::abs(Clamp(angle) - angle_) / speed); }
  // Moves the goal linearly to `angle` over `seconds`.
  Pattern& Ramp(double angle, double seconds) {
    angle = Clamp(angle);
    const int rows = std::max(1, static_cast<int>(std::lround(seconds / step_)));
    const double from = angle_;
    for (int k = 1; k <= rows; ++k) Row(from + (angle - from) * k / rows);
    return *this;
  }
  // Jumps the goal to `angle`.
  Pattern& Step(double angle) {
    angle_ = Clamp(angle);
    return *this;
  }
  // The torque limit from the next row on.
  Pattern& Torque(double torque) {
    torque_ = torque;
    return *this;
  }

  std::vector<double> angles;   // per row, degrees
  std::vector<double> torques;  // per row

 private:
  double Clamp(double angle) const { return std::clamp(angle, lower_, upper_); }
  void Row(double angle) {
    angle_ = angle;
    angles.push_back(angle);
    torques.push_back(torque_);
  }

  double step_;
  double lower_;
  double upper_;
  double angle_ = 0.0;
  double torque_ = 1.0;
};

// Where a probe moves about, within the motor's stops: its centre (0° where the stops leave 10° on both sides) and
// an amplitude of at most 40°.
struct Span {
  double centre = 0.0;
  double amplitude = 0.0;
};

Span SpanOf(double lower, double upper) {
  constexpr double kMargin = 10.0;
  constexpr double kAmplitude = 40.0;
  Span span;
  span.centre = std::clamp(0.0, lower + kMargin, std::max(lower + kMargin, upper - kMargin));
  span.amplitude = std::max(0.0, std::min({kAmplitude, span.centre - lower - kMargin / 2, upper - span.centre - kMargin / 2}));
  if (span.amplitude < 5.0) span.amplitude = std::max(0.0, (upper - lower) / 2 - 1.0);
  return span;
}

ProbeMotion Make(const std::string& name, const std::string& description, const std::string& shows,
                 const std::string& motor, Pattern pattern) {
  return {name, description, shows, motor, std::move(pattern.angles), std::move(pattern.torques)};
}

std::vector<ProbeMotion> Probes(const std::string& motor, double step, double lower, double upper) {
  const Span s = SpanOf(lower, upper);
  const double c = s.centre;
  const double a = s.amplitude;
  std::vector<ProbeMotion> probes;
  {
    Pattern p(step, lower, upper);
    p.Step(c).Hold(1.0);
    for (double speed : {4.0, 15.0}) {
      p.RampAt(c + a / 2, speed).Hold(1.0).RampAt(c - a / 2, speed).Hold(1.0).RampAt(c, speed).Hold(1.0);
    }
    probes.push_back(Make("slow_reversals", "slow moves of ±" + text::FormatDouble(a / 2) +
                                                "° at 4 and 15 °/s, each reversal held 1 s",
                         "friction at low speed and its memory (Stribeck, LuGre, backlash)", motor, std::move(p)));
  }
  {
    Pattern p(step, lower, upper);
    p.Step(c - a).Hold(1.0);
    for (double speed : {10.0, 30.0, 90.0, 180.0}) p.RampAt(c + a, speed).Hold(0.5).RampAt(c - a, speed).Hold(0.5);
    p.RampAt(c, 30.0).Hold(0.5);
    probes.push_back(Make("speed_ladder", "sweeps over ±" + text::FormatDouble(a) + "° at 10, 30, 90 and 180 °/s",
                          "friction and torque against speed (Stribeck's velocity, back-EMF)", motor, std::move(p)));
  }
  {
    Pattern p(step, lower, upper);
    p.Step(c).Hold(0.5).RampAt(c + a, 60.0).Hold(1.0);
    for (double torque : {0.5, 0.35}) {
      p.Torque(torque).Hold(1.0).RampAt(c, 8.0).Hold(1.0).RampAt(c + a, 8.0).Hold(1.0);
    }
    p.Torque(1.0).RampAt(c, 30.0).Hold(0.5);
    probes.push_back(Make("loaded_lowering", "a load lowered and lifted at 8 °/s between " + text::FormatDouble(c) +
                                                 "° and " + text::FormatDouble(c + a) + "° at torque limits 0.5 and 0.35",
                          "friction that grows with the load, lowering against lifting (LoadFriction, BackDrive, "
                          "GravityLoadFriction)",
                          motor, std::move(p)));
  }
  {
    Pattern p(step, lower, upper);
    p.Step(c).Hold(0.5);
    for (double target : {c + a, c - a, c + a / 2, c}) p.Step(target).Hold(1.5);
    probes.push_back(Make("fast_steps", "steps of up to " + text::FormatDouble(2 * a) + "° at full torque, held 1.5 s",
                          "the response to fast steps (delay, elasticity, rotor inertia)", motor, std::move(p)));
  }
  {
    Pattern p(step, lower, upper);
    p.Step(c + a / 2).Hold(1.0);
    double sign = 1.0;
    for (double size : {0.5, 1.0, 2.0, 3.0, 5.0}) {
      p.Step(c + a / 2 + sign * size).Hold(1.0).Step(c + a / 2).Hold(1.0);
      sign = -sign;
    }
    probes.push_back(Make("small_steps", "steps of 0.5, 1, 2, 3 and 5° about " + text::FormatDouble(c + a / 2) +
                                             "°, each held 1 s",
                          "small moves (dead band, backlash, stiction)", motor, std::move(p)));
  }
  {
    Pattern p(step, lower, upper);
    for (double side : {1.0, -1.0}) {
      p.Torque(1.0).RampAt(c + side * a, 60.0).Hold(1.0).Torque(0.0).Hold(1.5).Torque(1.0).Hold(0.5);
    }
    p.RampAt(c, 60.0).Hold(0.5);
    probes.push_back(Make("limp_drops", "held at ±" + text::FormatDouble(a) + "°, then limp (torque 0) for 1.5 s",
                          "the gearbox's friction without the motor's drive (the limp servo's fall)", motor,
                          std::move(p)));
  }
  {
    Pattern p(step, lower, upper);
    p.Step(c).Hold(0.5);
    for (double torque : {0.1, 0.2, 0.3, 0.45}) {
      p.Torque(torque).RampAt(c + a, 20.0).Hold(1.0).Torque(1.0).RampAt(c, 30.0).Hold(0.5);
    }
    probes.push_back(Make("torque_ladder", "lifts to " + text::FormatDouble(c + a) +
                                               "° at torque limits 0.1, 0.2, 0.3 and 0.45",
                          "where torque-limited lifts stall (friction at the torque limit, load friction)", motor,
                          std::move(p)));
  }
  return probes;
}

std::size_t MotorIndex(const Rig& rig, const std::string& motor) {
  const auto found = std::find(rig.motors.begin(), rig.motors.end(), motor);
  if (found == rig.motors.end()) {
    throw InputError("--probe-motor: agent '" + rig.agent + "' of " + rig.environment_name + " has no motor " +
                     text::Quote(motor));
  }
  return static_cast<std::size_t>(found - rig.motors.begin());
}

}  // namespace

const std::vector<std::string_view>& ProbeNames() {
  static const std::vector<std::string_view> names = {"slow_reversals", "speed_ladder", "loaded_lowering",
                                                      "fast_steps",     "small_steps",  "limp_drops",
                                                      "torque_ladder"};
  return names;
}

std::vector<ProbeMotion> ProbeMotions(const Rig& rig, const std::string& motor) {
  const std::size_t index = MotorIndex(rig, motor);
  const auto [lower, upper] = rig.motor_ranges.at(index);
  return Probes(motor, rig.step, lower, upper);
}

ProbeMotion FindProbe(const Rig& rig, const std::string& motor,
                      const std::string& name) {
  for (ProbeMotion& probe : ProbeMotions(rig, motor)) {
    if (probe.name == name) return std::move(probe);
  }
  std::string names;
  for (std::string_view known : ProbeNames()) names += (names.empty() ? "" : ", ") + std::string(known);
  throw InputError("--probe: no probe motion " + text::Quote(name) + " (known: " + names + ")");
}

MeasuredRun ProbeRun(const Rig& rig, const ProbeMotion& probe, const MeasuredRun* like) {
  MeasuredRun run;
  run.source = "probe:" + probe.name;
  run.agent = rig.agent;
  run.motors = rig.motors;
  run.commanded = rig.motors;
  run.step = rig.step;
  const std::size_t rows = probe.angle.size() + 1;  // row 0: the state after the reset
  for (std::size_t k = 0; k < rows; ++k) {
    run.time.push_back(static_cast<double>(k) * rig.step);
    run.lines.push_back(0);
  }
  for (const std::string& motor : rig.motors) {
    std::vector<double>& angle = run.desired_angle[motor];
    std::vector<double>& torque = run.desired_torque[motor];
    if (motor == probe.motor) {
      angle.push_back(probe.angle.front());
      angle.insert(angle.end(), probe.angle.begin(), probe.angle.end());
      torque.push_back(probe.torque.front());
      torque.insert(torque.end(), probe.torque.begin(), probe.torque.end());
    } else {
      angle.assign(rows, 0.0);
      torque.assign(rows, aseries::kDefaultDesiredTorqueRaw);
    }
    run.joint_angle[motor].assign(rows, 0.0);
  }
  if (like != nullptr && !like->firmware_kp.empty()) {
    run.firmware_kp.assign(rows, like->firmware_kp.front());
    run.firmware_kp_column = like->firmware_kp_column;
  }
  return run;
}

}  // namespace orcs::identify
