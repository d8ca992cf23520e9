// What orcs-robot plays: a source of each control period's commands for the map's joints — a keyframe record, or
// any orcs controller (a neural network genome from evolve, an oscillator, a script) run on the simulated twin's
// values with the robot's measured angles as its joint sensors.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "hardware/robot/joint_map.h"
#include "hardware/robot/simulated_twin.h"
#include "model/control/controller.h"
#include "model/control/keyframe_record.h"

namespace orcs::hardware {

class CommandSource {
 public:
  virtual ~CommandSource() = default;
  /// Seconds of motion: the run ends at the first period after it.
  virtual double duration() const = 0;
  /// Whether the source has ended before its duration (a motion editor disconnected): the run ends at the next
  /// period, its state logged.
  virtual bool finished() const { return false; }
  /// The commands (degrees and torque 0…1 per joint, in the map's order, not yet clamped) for the period that
  /// starts at `time` s, given the joints' measured angles (degrees).
  virtual void Commands(double time, const std::vector<double>& measured, std::vector<double>& goal,
                        std::vector<double>& torque) = 0;
};

/// A keyframe record (raw layout, the map's joints in order): the latest row whose time is not after the period's.
class RecordSource final : public CommandSource {
 public:
  explicit RecordSource(control::KeyframeRecord record) : record_(std::move(record)) {}
  double duration() const override { return record_.frames.back().time_ms / 1000.0; }
  void Commands(double time, const std::vector<double>& measured, std::vector<double>& goal,
                std::vector<double>& torque) override;
  const control::KeyframeRecord& record() const { return record_; }

 private:
  control::KeyframeRecord record_;
};

/// A scenario's controller with a genome, run on the twin's simulation: each period the robot's measured angles
/// become the twin's joint sensors (/Sim/<agent>/<joint>/JointAngle), the controller updates, and the inputs it
/// writes (DesiredAngle, DesiredTorque) are the commands. Its other sensors (accelerometers) are the twin's.
class ControllerSource final : public CommandSource {
 public:
  /// `scenario` is the scenario file (its "controller" section and, without `genome`, its "genome"); `duration`
  /// seconds, or the scenario's when 0. Throws InputError naming the scenario or the genome.
  ControllerSource(const std::string& scenario, const nlohmann::json* genome, double duration, SimulatedTwin& twin,
                   const JointMap& map);
  ~ControllerSource() override;
  double duration() const override { return duration_; }
  void Commands(double time, const std::vector<double>& measured, std::vector<double>& goal,
                std::vector<double>& torque) override;

 private:
  SimulatedTwin& twin_;                              // whose values the controller reads and writes
  std::unique_ptr<control::Controller> controller_;  // the scenario's, for the genome
  double duration_ = 0.0;                            // s
};

}  // namespace orcs::hardware
