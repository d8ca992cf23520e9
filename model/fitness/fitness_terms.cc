#include "model/fitness/fitness_terms.h"

#include <cmath>
#include <limits>

#include "model/control/keyframe_record.h"
#include "model/core/error.h"
#include "model/core/text.h"
#include "model/fitness/plugin_term.h"
#include "model/fitness/script_term.h"

namespace orcs::fitness {
namespace {

// The physics body index of an agent's body given by its morphology name ("Middle/Head").
int AgentBody(const JsonNode& entry, const scene::Simulation& simulation, int agent_index) {
  const JsonNode node = entry.At("body");
  const std::string name = node.String("a body name like \"Middle/Head\"");
  const int body = simulation.model().morphology(agent_index).FindBody(name);
  if (body < 0) node.Fail("a body of agent " + text::Quote(simulation.model().agents()[agent_index].agent_name));
  return simulation.model().agents()[agent_index].bodies[body];
}

double MinHeight(const JsonNode& entry) { return entry.At("min_height").Number("a height in m"); }

class Distance : public FitnessTerm {
 public:
  Distance(int body, int axis) : body_(body), axis_(axis) {}
  void Start(const scene::Simulation& s) override { start_ = now_ = s.physics().body_state(body_).position[axis_]; }
  void Sample(const scene::Simulation& s, double) override { now_ = s.physics().body_state(body_).position[axis_]; }
  double value() const override { return now_ - start_; }

 private:
  int body_, axis_;
  double start_ = 0.0, now_ = 0.0;
};

class PathLength : public FitnessTerm {
 public:
  PathLength(int body, int axis) : body_(body), axis_(axis) {}
  void Start(const scene::Simulation& s) override {
    last_ = s.physics().body_state(body_).position[axis_];
    length_ = 0.0;
  }
  void Sample(const scene::Simulation& s, double) override {
    const double now = s.physics().body_state(body_).position[axis_];
    length_ += std::abs(now - last_);
    last_ = now;
  }
  double value() const override { return length_; }

 private:
  int body_, axis_;
  double last_ = 0.0, length_ = 0.0;
};

class UprightTime : public FitnessTerm {
 public:
  UprightTime(int body, double min_height) : body_(body), min_height_(min_height) {}
  void Start(const scene::Simulation&) override { seconds_ = 0.0; }
  void Sample(const scene::Simulation& s, double dt) override {
    if (s.physics().body_state(body_).position.y() >= min_height_) seconds_ += dt;
  }
  double value() const override { return seconds_; }

 private:
  int body_;
  double min_height_;
  double seconds_ = 0.0;
};

class FinalHeight : public FitnessTerm {
 public:
  explicit FinalHeight(int body) : body_(body) {}
  void Start(const scene::Simulation& s) override { height_ = s.physics().body_state(body_).position.y(); }
  void Sample(const scene::Simulation& s, double) override { height_ = s.physics().body_state(body_).position.y(); }
  double value() const override { return height_; }

 private:
  int body_;
  double height_ = 0.0;
};

class Energy : public FitnessTerm {
 public:
  explicit Energy(std::vector<int> motors) : motors_(std::move(motors)) {}
  void Start(const scene::Simulation&) override { joules_ = 0.0; }
  void Sample(const scene::Simulation& s, double dt) override {
    for (int joint : motors_) {
      joules_ += std::abs(s.physics().joint_motor_torque(joint) * s.physics().joint_rate(joint)) * dt;
    }
  }
  double value() const override { return joules_; }

 private:
  std::vector<int> motors_;
  double joules_ = 0.0;
};

// Compares every motor's JointAngle after a step with the record's DesiredAngle in force during it.
class TrackingError : public FitnessTerm {
 public:
  TrackingError(control::KeyframeRecord record, std::vector<const Value*> angles)
      : record_(std::move(record)), angles_(std::move(angles)) {}
  void Start(const scene::Simulation& s) override {
    sum_ = 0.0;
    count_ = 0;
    row_ = 0;
    step_start_ = s.time();
  }
  void Sample(const scene::Simulation& s, double) override {
    const double start_ms = step_start_ * 1000.0 + 1e-6;
    while (row_ + 1 < record_.frames.size() && record_.frames[row_ + 1].time_ms <= start_ms) ++row_;
    step_start_ = s.time();
    if (record_.frames[row_].time_ms > start_ms) return;  // before the first row: nothing commanded yet
    for (std::size_t m = 0; m < angles_.size(); ++m) {
      const double error = angles_[m]->as_double() - record_.frames[row_].inputs[2 * m];
      sum_ += error * error;
      ++count_;
    }
  }
  double value() const override { return count_ == 0 ? 0.0 : std::sqrt(sum_ / static_cast<double>(count_)); }

 private:
  control::KeyframeRecord record_;
  std::vector<const Value*> angles_;
  double sum_ = 0.0;
  long count_ = 0;
  std::size_t row_ = 0;
  double step_start_ = 0.0;
};

// The error of the simulated joint angles (and accelerometer axes, weighted into degrees) against measured ones,
// RMS or mean absolute over every listed entry: the gap workflow's replays (model/identify/replay.h).
class MeasuredError : public FitnessTerm {
 public:
  // One compared channel: what it reads, what was measured after each step, and its weight (1 for an angle; deg
  // per m/s² for an accelerometer axis).
  struct Channel {
    const Value* value = nullptr;
    std::vector<double> measured;
    double weight = 1.0;
  };

  MeasuredError(std::vector<Channel> channels, bool absolute, double stop_above)
      : channels_(std::move(channels)), absolute_(absolute), stop_above_(stop_above) {
    for (const Channel& channel : channels_) listed_ += static_cast<long>(channel.measured.size());
  }
  void Start(const scene::Simulation&) override {
    sum_ = 0.0;
    count_ = 0;
    step_ = 0;
    finished_ = false;
  }
  void Sample(const scene::Simulation&, double) override {
    for (const Channel& channel : channels_) {
      if (step_ >= channel.measured.size()) continue;
      const double error = channel.weight * (channel.value->as_double() - channel.measured[step_]);
      sum_ += absolute_ ? std::abs(error) : error * error;
      ++count_;
    }
    ++step_;
    // The entries still to come add nothing below: the norm over all of them is a lower bound of the final value.
    finished_ = listed_ > 0 && Norm(listed_) > stop_above_;
  }
  double value() const override {
    if (finished_) return Norm(listed_);
    return count_ == 0 ? 0.0 : Norm(count_);
  }
  bool finished() const override { return finished_; }

 private:
  // RMS or mean absolute error over `entries` entries, degrees.
  double Norm(long entries) const {
    const double mean = sum_ / static_cast<double>(entries);
    return absolute_ ? mean : std::sqrt(mean);
  }

  std::vector<Channel> channels_;  // the motors' JointAngle values, then the accelerometer axes
  bool absolute_;                  // "norm": "mean_absolute" (else RMS)
  double stop_above_;              // degrees in the norm; +∞ = run to the end
  long listed_ = 0;                // entries over all channels
  double sum_ = 0.0;               // Σ error² (deg²) or Σ |error| (deg)
  long count_ = 0;                 // entries compared so far
  std::size_t step_ = 0;
  bool finished_ = false;          // the norm over all listed entries exceeds stop_above_
};

class Falls : public FitnessTerm {
 public:
  Falls(int body, double min_height) : body_(body), min_height_(min_height) {}
  void Start(const scene::Simulation& s) override {
    falls_ = 0;
    above_ = s.physics().body_state(body_).position.y() >= min_height_;
  }
  void Sample(const scene::Simulation& s, double) override {
    const bool above = s.physics().body_state(body_).position.y() >= min_height_;
    if (above_ && !above) ++falls_;
    above_ = above;
  }
  double value() const override { return static_cast<double>(falls_); }

 private:
  int body_;
  double min_height_;
  int falls_ = 0;
  bool above_ = true;
};

int AxisOf(const JsonNode& node) {
  const std::string axis = node.String("\"x\", \"y\" or \"z\"");
  if (axis == "x") return 0;
  if (axis == "y") return 1;
  if (axis == "z") return 2;
  node.Fail("\"x\", \"y\" or \"z\"");
}

std::unique_ptr<FitnessTerm> MakeTrackingError(const JsonNode& entry, const scene::Simulation& simulation,
                                               int agent_index) {
  const JsonNode record = entry.At("record");
  if (!record.value().is_object()) record.Fail("an inlined record {\"file\", \"text\"} (resolve the scenario first)");
  record.ExpectOnly({"file", "text"});
  const aseries::ASeriesLayout& layout = simulation.model().agents()[agent_index];
  const aseries::ASeriesMorphology& morphology = simulation.model().morphology(agent_index);
  control::KeyframeRecord parsed =
      control::ParseKeyframeRecord(record.At("text").String("the record's text"),
                                   record.StringOr("file", record.path(), "a file name"),
                                   static_cast<int>(morphology.motors.size()));
  std::vector<const Value*> angles;
  for (const aseries::MorphologyMotor& motor : morphology.motors) {
    angles.push_back(&simulation.repository().Get("/Sim/" + layout.agent_name + "/" + motor.name + "/JointAngle"));
  }
  return std::make_unique<TrackingError>(std::move(parsed), std::move(angles));
}

std::unique_ptr<FitnessTerm> MakeMeasuredError(const JsonNode& entry, const scene::Simulation& simulation,
                                               int agent_index) {
  const JsonNode angles = entry.At("angles");
  if (!angles.value().is_object()) angles.Fail("an object {\"<motor>\": [degrees, ...]}");
  const std::string prefix = "/Sim/" + simulation.model().agents()[agent_index].agent_name + "/";
  std::vector<MeasuredError::Channel> channels;
  for (const auto& [motor, list] : angles.Members()) {
    MeasuredError::Channel& channel = channels.emplace_back();
    channel.value = simulation.repository().Find(prefix + motor + "/JointAngle");
    if (channel.value == nullptr) list.Fail("the angles of a motor of the agent");
    for (const JsonNode& element : list.Elements()) channel.measured.push_back(element.Number("a finite angle in degrees"));
  }
  if (entry.Has("accelerations")) {
    const JsonNode accelerations = entry.At("accelerations");
    if (!accelerations.value().is_object()) {
      accelerations.Fail("an object {\"<board>/AccelAxis1\": {\"values\": [m/s², ...], \"weight\": deg per m/s²}}");
    }
    for (const auto& [axis, node] : accelerations.Members()) {
      node.ExpectOnly({"values", "weight"});
      MeasuredError::Channel& channel = channels.emplace_back();
      const bool is_axis = axis.size() > 10 && (axis.ends_with("/AccelAxis1") || axis.ends_with("/AccelAxis2"));
      channel.value = is_axis ? simulation.repository().Find(prefix + axis) : nullptr;
      if (channel.value == nullptr) node.Fail("the readings of an accelerometer axis of the agent (\"ABSR/AccelAxis1\")");
      for (const JsonNode& element : node.At("values").Elements()) {
        channel.measured.push_back(element.Number("a finite acceleration in m/s²"));
      }
      channel.weight = node.At("weight").Number("a positive weight in degrees per m/s²");
      if (!(channel.weight > 0.0)) node.At("weight").Fail("a positive weight in degrees per m/s²");
    }
  }
  bool absolute = false;
  if (entry.Has("norm")) {
    const std::string norm = entry.At("norm").String("\"rms\" or \"mean_absolute\"");
    if (norm != "rms" && norm != "mean_absolute") entry.At("norm").Fail("\"rms\" or \"mean_absolute\"");
    absolute = norm == "mean_absolute";
  }
  double stop_above = std::numeric_limits<double>::infinity();
  if (entry.Has("stop_above")) {
    stop_above = entry.At("stop_above").Number("an error in degrees, at least 0");
    if (stop_above < 0) entry.At("stop_above").Fail("an error in degrees, at least 0");
  }
  return std::make_unique<MeasuredError>(std::move(channels), absolute, stop_above);
}

}  // namespace

std::unique_ptr<FitnessTerm> MakeFitnessTerm(const JsonNode& entry, const scene::Simulation& simulation,
                                             int agent_index, const script::PluginRegistry* plugins) {
  const std::string type = entry.At("type").String(kFitnessTermTypes);
  if (type == "distance") {
    entry.ExpectOnly({"type", "name", "weight", "body", "axis"});
    return std::make_unique<Distance>(AgentBody(entry, simulation, agent_index), AxisOf(entry.At("axis")));
  }
  if (type == "path_length") {
    entry.ExpectOnly({"type", "name", "weight", "body", "axis"});
    return std::make_unique<PathLength>(AgentBody(entry, simulation, agent_index), AxisOf(entry.At("axis")));
  }
  if (type == "upright_time") {
    entry.ExpectOnly({"type", "name", "weight", "body", "min_height"});
    return std::make_unique<UprightTime>(AgentBody(entry, simulation, agent_index), MinHeight(entry));
  }
  if (type == "final_height") {
    entry.ExpectOnly({"type", "name", "weight", "body"});
    return std::make_unique<FinalHeight>(AgentBody(entry, simulation, agent_index));
  }
  if (type == "energy") {
    entry.ExpectOnly({"type", "name", "weight"});
    return std::make_unique<Energy>(simulation.model().agents()[agent_index].motors);
  }
  if (type == "tracking_error") {
    entry.ExpectOnly({"type", "name", "weight", "record"});
    return MakeTrackingError(entry, simulation, agent_index);
  }
  if (type == "measured_error") {
    entry.ExpectOnly({"type", "name", "weight", "angles", "accelerations", "norm", "stop_above"});
    return MakeMeasuredError(entry, simulation, agent_index);
  }
  if (type == "script") {
    entry.ExpectOnly({"type", "name", "weight", "script", "params", "limits"});
    return std::make_unique<ScriptTerm>(script::ParseScriptSpec(entry), simulation, agent_index);
  }
  if (type == "plugin") {
    entry.ExpectOnly({"type", "name", "weight", "plugin", "params"});
    return std::make_unique<PluginTerm>(entry, simulation, agent_index, plugins);
  }
  if (type == "falls") {
    entry.ExpectOnly({"type", "name", "weight", "body", "min_height"});
    return std::make_unique<Falls>(AgentBody(entry, simulation, agent_index), MinHeight(entry));
  }
  entry.At("type").Fail(kFitnessTermTypes);
}

}  // namespace orcs::fitness
