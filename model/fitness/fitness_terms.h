// The fitness terms (docs/scenarios.md, "fitness"). A term watches one simulation run: Start after the reset,
// Sample after every simulation step, value() at the end. Every term is reported on its own and weighted into
// the fitness by FitnessFunction.
//
//   distance        {"body": "Middle/UpperBody", "axis": "z"}   final − start position along the axis, m
//   path_length     {"body": "Middle/UpperBody", "axis": "x"}   Σ over steps of |Δ position along the axis|, m: how
//                   far the body travelled to and fro (rocking from foot to foot sways it sideways)
//   upright_time    {"body": "Middle/Head", "min_height": 0.3}  simulated seconds with the body at least that high, s
//   final_height    {"body": "Middle/Head"}                     height of the body at the end, m
//   energy          {}                                          Σ over steps and motors of |τ·ω|·dt, J
//   tracking_error  {"record": {"file", "text"}}                RMS of JointAngle − the record's DesiredAngle, degrees
//   falls           {"body": "Middle/Head", "min_height": 0.2}  times the body went from above to below the height
//   measured_error  {"angles": {"Right/Knee": [deg, ...], ...}}  RMS of JointAngle − a measured run's angle after
//                   each step (entry k after step k+1; steps beyond the list are not compared), pooled over the
//                   listed motors, degrees: orcs-gap's objective (docs/gap.md). Optional "norm": "rms" (the
//                   default) or "mean_absolute" (the mean of |JointAngle − measured|, degrees: orcs-gap --loss
//                   absolute). Optional "stop_above" (degrees in the norm, ≥ 0): the run stops as soon as the value
//                   can no longer end at or below it — when the norm so far, counted over *every* listed entry,
//                   exceeds it. The value is then that norm: a lower bound of the whole run's, above stop_above. A
//                   fit's search uses it for points that cannot beat its best.
//   script          {"script": "x.lua", "params": {...}, "limits": {...}}   the script's finish(), in its own unit; its
//                   stop() may end the run early (model/fitness/script_term.h, docs/extending.md)
//   plugin          {"plugin": "example/mean_height", "params": {...}}   a compiled plug-in's term, loaded by the
//                   worker (model/fitness/plugin_term.h)
#pragma once

#include <memory>
#include <string>

#include "model/core/json_node.h"
#include "model/scene/simulation.h"

namespace orcs::script {
class PluginRegistry;
}  // namespace orcs::script

namespace orcs::fitness {

class FitnessTerm {
 public:
  virtual ~FitnessTerm() = default;
  /// After the simulation's reset, before the first step.
  virtual void Start(const scene::Simulation& simulation) = 0;
  /// After every simulation step of `dt` seconds.
  virtual void Sample(const scene::Simulation& simulation, double dt) = 0;
  /// The term's value for the run so far.
  virtual double value() const = 0;
  /// Whether the run may stop here: further steps cannot change what the term was asked (measured_error's
  /// "stop_above"). Most terms never finish.
  virtual bool finished() const { return false; }
};

/// The term a fitness entry describes, for agent `agent_index` of `simulation` (built). Throws InputError naming
/// the field for an unknown type, key, body or axis.
/// `plugins`: the plug-in components of this process, for "type": "plugin" (null: none; such a term then throws
/// script::PluginMissing).
std::unique_ptr<FitnessTerm> MakeFitnessTerm(const JsonNode& entry, const scene::Simulation& simulation,
                                             int agent_index, const script::PluginRegistry* plugins = nullptr);

/// The type names MakeFitnessTerm knows.
inline constexpr const char* kFitnessTermTypes =
    "\"distance\", \"path_length\", \"upright_time\", \"final_height\", \"energy\", \"tracking_error\", \"falls\", "
    "\"measured_error\", \"script\" or \"plugin\"";

}  // namespace orcs::fitness
