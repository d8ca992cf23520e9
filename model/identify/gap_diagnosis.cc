#include "model/identify/gap_diagnosis.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <condition_variable>
#include <future>
#include <memory>
#include <mutex>
#include <sstream>

#include "base/demand.h"
#include "model/identify/effect_catalogue.h"
#include "model/identify/least_squares_polish.h"
#include "model/core/error.h"
#include "model/core/text.h"

namespace orcs::identify {
namespace {

// The model's own parameters: what a mistuned model gets wrong before anything is missing (spec §6e).
const std::vector<FitParameter> kBase = {
    {"/AngularMotor/PID/Proportional", "1/s", 2.0, 100.0},
    {"/AngularMotor/FMaxFactor", "N·m", 0.3, 3.0},
    {"/AngularMotor/DynamicFriction", "N·m·s/rad", 0.005, 1.0},
};
// The physical servo's (servo_motor.h): the DC motor's torque per volt (kt, with R fixed: only kt/R and kt·ke/R
// show in the motion) and back-EMF, the armature and the gearbox friction. Never the firmware gain: each run
// gives its own. The gain's scale stays the datasheet's, so that one fit serves every gain.
const std::vector<FitParameter> kServoBase = {
    {"/Servo/TorqueConstant", "N·m/A", 0.02, 5.0},
    {"/Servo/BackEmfConstant", "V·s/rad", 0.02, 5.0},
    {"/Servo/Armature", "kg·m²", 1e-5, 0.05},
    {"/Servo/CoulombFriction", "N·m", 1e-4, 0.5},
    {"/Servo/ViscousFriction", "N·m·s/rad", 1e-4, 0.5},
};

// With a current limit (/Servo/CurrentLimit > 0) the motor's torque ceiling is kt × the limit, set by kt alone, and
// the runs at one gain seldom reach it: a fitted kt moves the ceiling where the other gains need it (docs/gap.md, "A
// real servo"). So kt and ke stay the model's (the datasheet's) and R carries kt/R and kt·ke/R instead.
const std::vector<FitParameter> kCurrentLimitedServoBase = {
    {"/Servo/Resistance", "Ω", 0.1, 50.0},
    {"/Servo/Armature", "kg·m²", 1e-5, 0.05},
    {"/Servo/CoulombFriction", "N·m", 1e-4, 0.5},
    {"/Servo/ViscousFriction", "N·m·s/rad", 1e-4, 0.5},
};

std::string EnabledPath(const EffectDescription& effect) { return "/Effects/" + std::string(effect.name) + "/Enabled"; }

std::vector<ReplayRun> Concatenate(const std::vector<ReplayRun>& a, const std::vector<ReplayRun>& b) {
  std::vector<ReplayRun> all = a;
  all.insert(all.end(), b.begin(), b.end());
  return all;
}

double Rms(double mse) { return std::sqrt(mse); }

double LossOf(ReplayEvaluator& replays, const std::vector<ReplayRun>& runs, const std::vector<Override>& model,
              Loss loss) {
  return ReplayObjective(replays, runs, {}, loss).Losses({model})[0];
}

double MeanSquaredError(ReplayEvaluator& replays, const std::vector<ReplayRun>& runs, const std::vector<Override>& model) {
  return LossOf(replays, runs, model, Loss::kSquared);
}

std::vector<FittedValue> Report(const std::vector<FitParameter>& parameters, const FitOutcome& fit) {
  std::vector<FittedValue> report;
  for (std::size_t i = 0; i < parameters.size(); ++i) {
    const double ci95 = i < fit.ci95.size() ? fit.ci95[i] : std::numeric_limits<double>::quiet_NaN();
    const BoundState bound = i < fit.bounds.size() ? fit.bounds[i] : BoundState::kInside;
    report.push_back({parameters[i].path, parameters[i].unit, parameters[i].start, fit.values[i], ci95,
                      Identified(fit.values[i], ci95), bound});
  }
  return report;
}

// The replays of one model with logs, as per-run channel traces: measured, simulated, desired, motor torque. With
// `recordings`, the replays are recorded too (recording changes no bits) and their recordings kept by run name.
std::vector<std::vector<ChannelTrace>> Traces(ReplayEvaluator& replays, const std::vector<ReplayRun>& runs,
                                              const std::vector<Override>& model,
                                              std::map<std::string, std::string>* recordings) {
  std::vector<ReplayRequest> requests;
  for (const ReplayRun& run : runs) requests.push_back({&run, model, /*log=*/true, /*record=*/recordings != nullptr});
  std::vector<ReplayOutcome> outcomes = replays.Replay(requests);
  std::vector<std::vector<ChannelTrace>> traces;
  for (std::size_t r = 0; r < runs.size(); ++r) {
    const MeasuredRun& measured = *runs[r].run;
    if (recordings != nullptr && !outcomes[r].recording.empty()) {
      (*recordings)[runs[r].name] = std::move(outcomes[r].recording);
    }
    const auto& columns = outcomes[r].columns;
    const auto column = [&columns](const std::string& path) -> std::vector<double> {
      for (const auto& [name, values] : columns) {
        if (name == path) return values;
      }
      return {};
    };
    std::vector<ChannelTrace>& run_traces = traces.emplace_back();
    for (const std::string& motor : runs[r].channels) {
      ChannelTrace trace;
      trace.name = runs[r].name + ":" + motor;
      trace.measured = measured.joint_angle.at(motor);
      trace.desired = measured.desired_angle.at(motor);
      const std::string prefix = "/Sim/" + measured.agent + "/" + motor + "/";
      trace.simulated = column(prefix + "JointAngle");
      trace.motor_torque = column(prefix + "MotorTorque");
      // A failed replay (unstable physics) compares against NaN: the statistics show it, nothing crashes.
      trace.simulated.resize(trace.measured.size(), std::nan(""));
      if (!trace.motor_torque.empty()) trace.motor_torque.resize(trace.measured.size(), 0.0);
      run_traces.push_back(std::move(trace));
    }
  }
  return traces;
}

// `record`: keep the replays' recordings (GapSnapshot::recordings).
GapSnapshot Snapshot(ReplayEvaluator& replays, const std::vector<ReplayRun>& fit, const std::vector<ReplayRun>& holdout,
                     const std::vector<Override>& model, double step, bool record) {
  GapSnapshot snapshot;
  snapshot.fit_rms = Rms(MeanSquaredError(replays, fit, model));
  snapshot.holdout_rms = Rms(MeanSquaredError(replays, holdout, model));
  const std::vector<ReplayRun> runs = Concatenate(fit, holdout);
  snapshot.traces = Traces(replays, runs, model, record ? &snapshot.recordings : nullptr);
  std::vector<ChannelTrace> all;  // a replay that failed (unstable physics) has no trace to analyse
  for (std::size_t r = 0; r < snapshot.traces.size(); ++r) {
    bool failed = false;
    for (const ChannelTrace& trace : snapshot.traces[r]) {
      if (std::all_of(trace.simulated.begin(), trace.simulated.end(), [](double v) { return std::isfinite(v); })) {
        all.push_back(trace);
      } else {
        failed = true;
      }
    }
    constexpr double kMilliradiansPerDegree = 1000.0 * std::numbers::pi / 180.0;
    const double nan = std::nan("");
    snapshot.runs.push_back({runs[r].name, r >= fit.size(), failed ? nan : GapRms(snapshot.traces[r]),
                             failed ? nan : GapMeanAbsolute(snapshot.traces[r]) * kMilliradiansPerDegree});
  }
  snapshot.channels = AnalyseChannels(all, step);
  return snapshot;
}

// The fit and its held-out loss; the RMS figures the report gives beside them cost more replays only with the
// absolute loss.
ModelScore ScoreFit(ReplayEvaluator& replays, const std::vector<ReplayRun>& fit, const std::vector<ReplayRun>& holdout,
                    const std::vector<FitParameter>& parameters, const std::vector<Override>& fixed,
                    const FitOptions& options, Loss loss) {
  ModelScore score;
  score.fit = Fit(ReplayObjective(replays, fit, fixed, loss), parameters, options);
  score.values = Report(parameters, score.fit);
  std::vector<Override> model = fixed;
  const std::vector<Override> fitted = OverridesOf(parameters, score.fit.values);
  model.insert(model.end(), fitted.begin(), fitted.end());
  score.holdout_loss = LossOf(replays, holdout, model, loss);
  const bool squared = loss == Loss::kSquared;
  score.fit_rms = Rms(squared ? score.fit.mse : MeanSquaredError(replays, fit, model));
  score.holdout_rms = Rms(squared ? score.holdout_loss : MeanSquaredError(replays, holdout, model));
  return score;
}

std::vector<Override> ModelOf(const ModelScore& score, const std::string& effect) {
  std::vector<Override> model;
  const EffectDescription* description = effect.empty() ? nullptr : FindEffect(effect);
  if (description != nullptr && description->switched) model.emplace_back("/Effects/" + effect + "/Enabled", "T");
  for (const FittedValue& value : score.values) model.emplace_back(value.path, text::FormatDouble(value.value));
  return model;
}

// The effects to try: the named ones, or the catalogue's defaults for the motor model (`servo`: the physical
// servo's). An effect the model switches on already is part of the base (BaseParameters), not a candidate.
std::vector<const EffectDescription*> Candidates(const std::vector<std::string>& names, bool servo,
                                                 const std::vector<const EffectDescription*>& enabled,
                                                 bool accelerometers) {
  const auto in_model = [&enabled](const EffectDescription* effect) {
    return std::find(enabled.begin(), enabled.end(), effect) != enabled.end();
  };
  std::vector<const EffectDescription*> candidates;
  if (names.empty()) {
    for (const EffectDescription& effect : EffectCatalogue()) {
      if (effect.needs_accelerometers && !accelerometers) continue;
      if ((servo ? effect.with_servo : effect.with_original) && !in_model(&effect)) candidates.push_back(&effect);
    }
    return candidates;
  }
  for (const std::string& name : names) {
    const EffectDescription* effect = FindEffect(name);
    if (effect == nullptr) throw InputError("--effects: no effect " + text::Quote(name) + " in the catalogue (docs/gap.md)");
    if (in_model(effect)) {
      throw InputError("--effects: " + text::Quote(name) + " is switched on in the model already (/Effects/" + name +
                       "/Enabled); its parameters are refitted with the base parameters, so it is no candidate");
    }
    if (servo && !effect->with_servo) {
      throw InputError("--effects: " + text::Quote(name) + " is part of the servo model (/Servo/Enabled) already or cannot "
                       "combine with it (docs/gap.md, \"A real servo\")");
    }
    candidates.push_back(effect);
  }
  return candidates;
}

bool HasAccelerometers(const std::vector<ReplayRun>& runs) {
  return std::any_of(runs.begin(), runs.end(), [](const ReplayRun& run) { return !run.accelerometers.empty(); });
}

std::string Percent(double fraction) { return text::FormatDouble(std::round(fraction * 1000.0) / 10.0) + " %"; }
std::string Degrees(double value) { return text::FormatDouble(std::round(value * 1000.0) / 1000.0) + "°"; }

const ModelScore& ScoreOf(const Diagnosis& d, const std::string& label) {
  for (const ModelScore& candidate : d.candidates) {
    if (candidate.label == label) return candidate;
  }
  ORCS_UNREACHABLE("ScoreOf: a label that is no candidate of the diagnosis");
}

// A rival's held-out gap against the named model's: "0.197° against 0.188°".
std::string Against(const Rival& rival, const Diagnosis& d, const DiagnosisOptions& options) {
  const auto gap = [&](const std::string& label) {
    const ModelScore& score = ScoreOf(d, label);
    return Degrees(options.loss == Loss::kAbsolute ? score.holdout_loss : score.holdout_rms);
  };
  return gap(rival.effect) + " against " + gap(d.effect) + (options.loss == Loss::kAbsolute ? " mean absolute" : " RMS");
}

// The advice of a probe comparison: `goal` is what the motion would do ("tell them apart"; `goal_s` as "a probe
// tells them apart"), `models` what it compares ("their fitted models").
std::string ProbeAdvice(const TellApart& t, const DiagnosisOptions& options, const std::string& goal,
                        const std::string& goal_s, const std::string& models) {
  if (t.probe.empty()) return "";
  std::ostringstream text;
  const double times = t.noise > 0.0 ? t.difference / t.noise : 0.0;
  if (times < 1.0) {
    text << " None of orcs's probe motions " << goal_s << ": " << models << " differ by at most "
         << Degrees(t.difference) << " RMS (" << t.probe << ", on " << t.motor << "), within the noise.";
    return text.str();
  }
  const std::string synth = options.synth_command.empty() ? "orcs-gap synth" : options.synth_command;
  text << " To " << goal << ", record " << t.description << " on " << t.motor << " (it shows " << t.shows
       << "): " << models << " differ there by " << Degrees(t.difference) << " RMS, "
       << text::FormatDouble(std::round(times * 10.0) / 10.0) << " times the noise. `" << synth << " --probe "
       << t.probe << " --probe-motor " << t.motor
       << " --out DIR` writes it as a keyframe record to play on the robot (DIR/motions/" << t.probe
       << ".csv); diagnose again with its measured run among the held-out runs.";
  return text.str();
}

std::string TellApartAdvice(const Diagnosis& d, const DiagnosisOptions& options) {
  return ProbeAdvice(d.tell_apart, options, "tell them apart", "tells them apart", "their fitted models");
}

// A loss as the verdict says it: the RMS (the squared loss's root) or the mean absolute error, in degrees.
std::string LossDegrees(double loss, const DiagnosisOptions& options) {
  return options.loss == Loss::kAbsolute ? Degrees(loss) + " mean absolute" : Degrees(std::sqrt(loss)) + " RMS";
}

// For each named effect, the open parameters whose value the held-out runs chose (open_parameter_probe.h).
std::string OpenParameterNotes(const Diagnosis& d, const DiagnosisOptions& options) {
  std::ostringstream text;
  for (const std::string& effect : d.effects) {
    for (const OpenParameter& open : ScoreOf(d, effect).open) {
      if (open.chosen == open.fitted) continue;
      const std::string name = open.path.substr(open.path.rfind('/') + 1);
      const auto number = [](double value) { return text::FormatSignificant(value, 4); };
      text << " " << effect << "'s " << name << " is not identified by the fit runs (" << number(open.fitted)
           << (std::isfinite(open.ci95) ? " ± " + number(open.ci95) : "") << " " << open.unit << "): "
           << open.equivalent << " of " << open.probed << " other values from " << number(open.low) << " to "
           << number(open.high) << " fit them as well, and the held-out runs choose " << number(open.chosen) << " ("
           << LossDegrees(open.holdout_loss, options) << " held out, against "
           << LossDegrees(open.holdout_loss_fitted, options) << " at the fit's value)."
           << ProbeAdvice(open.pin_down, options, "pin it down", "pins it down", "the models at the two values");
    }
  }
  return text.str();
}

std::string Verdict(const Diagnosis& d, const DiagnosisOptions& options) {
  std::ostringstream text;
  const double base = d.base.score;
  if (d.effect.empty()) {
    text << "No missing effect found: after refitting the base parameters the held-out gap is "
         << Degrees(d.base.holdout_rms) << " RMS, and no effect of the catalogue lowers the penalised score below "
         << Percent(options.win_ratio) << " of the refit's";
    if (!d.candidates.empty()) {
      text << " (best: " << d.candidates[0].label << ", " << Percent(d.candidates[0].score / base) << ")";
    }
    text << ".";
    return text.str();
  }
  const ModelScore& winner = ScoreOf(d, d.effect);
  if (d.effects.size() > 1) {
    text << "Missing effect: " << d.effects[0];
    for (std::size_t i = 1; i < d.effects.size(); ++i) text << (i + 1 == d.effects.size() ? " or " : ", ") << d.effects[i];
    text << ". The held-out runs cannot tell them apart:";
    for (const Rival& rival : d.rivals) {
      if (rival.contains_named) continue;
      text << " " << rival.effect << "'s held-out gap is within the noise of " << d.effect << "'s ("
           << Against(rival, d, options) << (rival.relation.empty() ? "" : "; " + rival.relation) << ").";
    }
    text << " With " << d.effect << " (" << winner.summary << ") the held-out gap falls from "
         << Degrees(d.before.holdout_rms) << " (model as given) and " << Degrees(d.base.holdout_rms)
         << " (base parameters refitted) to " << Degrees(winner.holdout_rms) << " RMS";
    for (std::size_t i = 1; i < d.effects.size(); ++i) {
      text << ", with " << d.effects[i] << " to " << Degrees(ScoreOf(d, d.effects[i]).holdout_rms);
    }
    text << "." << TellApartAdvice(d, options) << OpenParameterNotes(d, options);
    return text.str();
  }
  text << "Missing effect: " << d.effect << " (" << winner.summary << "). With it the held-out gap falls from "
       << Degrees(d.before.holdout_rms) << " (model as given) and " << Degrees(d.base.holdout_rms)
       << " (base parameters refitted) to " << Degrees(winner.holdout_rms) << " RMS; its penalised score is "
       << Percent(winner.score / base) << " of \"nothing missing\"";
  for (const ModelScore& other : d.candidates) {
    if (other.label == d.effect) continue;
    text << ", the runner-up " << other.label << " reaches " << Percent(other.score / base);
    break;
  }
  text << ".";
  for (const Rival& rival : d.rivals) {
    if (rival.contains_named) {
      text << " " << rival.effect << ", which contains it, fits the held-out runs no better (" << Against(rival, d, options)
           << "; " << rival.relation << ").";
    }
  }
  text << OpenParameterNotes(d, options);
  return text.str();
}

// The named effect and the candidates the held-out runs cannot tell from it (docs/gap.md, "When two effects explain
// the data"): every other candidate that also clears the naming bar and whose held-out RMS is within kTieRatio of
// the winner's is tied with it, unless one of the two contains the other exactly (EffectRelation::nested) — then the
// simpler is named alone.
void NameEffects(const DiagnosisOptions& options, Diagnosis& d) {
  d.effect = d.candidates[0].label;
  const auto gap = [&options](const ModelScore& s) {
    return options.loss == Loss::kAbsolute ? s.holdout_loss : s.holdout_rms;
  };
  const double named_gap = gap(d.candidates[0]);
  for (std::size_t i = 1; i < d.candidates.size(); ++i) {
    const ModelScore& c = d.candidates[i];
    if (!(c.score < options.win_ratio * d.base.score) || c.fit.abandoned) continue;
    const double ratio = named_gap > 0.0 ? gap(c) / named_gap : 1.0;
    if (!(ratio <= kTieRatio)) continue;
    const EffectRelation* relation = FindRelation(d.effect, c.label);
    Rival rival{c.label, ratio, relation != nullptr ? std::string(relation->text) : "", false};
    if (relation != nullptr && relation->nested) {
      // Nested and no better: the simpler of the two is named, the other said to add nothing.
      if (relation->first == d.effect) {
        rival.effect = d.effect;
        rival.ratio = 1.0 / ratio;
        d.effect = c.label;
      }
      rival.contains_named = true;
    }
    d.rivals.push_back(std::move(rival));
  }
  d.effects = {d.effect};
  for (const Rival& rival : d.rivals) {
    if (!rival.contains_named && rival.effect != d.effect) d.effects.push_back(rival.effect);
  }
}

// The motor whose motion a probe moves: the worst channel's of the model as given.
std::string WorstMotor(const Rig& rig, const Diagnosis& d) {
  const std::string& worst = d.before.channels.empty() ? rig.motors.front() : d.before.channels.front().name;
  return worst.substr(worst.find(':') + 1);
}

// For a tie: the probe motion on which the two first named models differ most.
TellApart BestProbe(ReplayEvaluator& replays, const Rig& rig, const std::vector<ValueAssignment>& model,
                    const std::vector<ReplayRun>& fit, const Diagnosis& d) {
  return CompareOnProbes(replays, rig, model, fit, WorstMotor(rig, d), ModelOf(ScoreOf(d, d.effects[0]), d.effects[0]),
                         ModelOf(ScoreOf(d, d.effects[1]), d.effects[1]), ScoreOf(d, d.effects[0]).holdout_rms);
}

// For each named effect whose open parameter the held-out runs moved: the probe motion on which the model at the
// fit's value and at the chosen one differ most, the measurement that would identify it.
void PinDownOpenParameters(ReplayEvaluator& replays, const Rig& rig, const std::vector<ValueAssignment>& model,
                           const std::vector<ReplayRun>& fit, Diagnosis& d) {
  for (ModelScore& score : d.candidates) {
    if (std::find(d.effects.begin(), d.effects.end(), score.label) == d.effects.end()) continue;
    for (OpenParameter& open : score.open) {
      if (open.chosen == open.fitted) continue;
      const std::vector<Override> chosen = ModelOf(score, score.label);
      std::vector<Override> fitted = chosen;
      for (auto& [path, value] : fitted) {
        if (path == open.path) value = text::FormatDouble(open.fitted);
      }
      open.pin_down = CompareOnProbes(replays, rig, model, fit, WorstMotor(rig, d), chosen, fitted, score.holdout_rms);
    }
  }
}

}  // namespace

std::vector<const EffectDescription*> EnabledEffects(const Rig& rig, const std::vector<ValueAssignment>& model) {
  std::vector<std::string> paths;
  std::vector<const EffectDescription*> switched;
  for (const EffectDescription& effect : EffectCatalogue()) {
    if (!effect.switched) continue;
    paths.push_back(EnabledPath(effect));
    switched.push_back(&effect);
  }
  const std::vector<bool> on = ModelSwitches(rig, model, paths);
  std::vector<const EffectDescription*> enabled;
  for (std::size_t i = 0; i < on.size(); ++i) {
    if (on[i]) enabled.push_back(switched[i]);
  }
  return enabled;
}

std::vector<FitParameter> BaseParameters(const Rig& rig, const std::vector<ValueAssignment>& model) {
  std::vector<FitParameter> parameters = kBase;
  if (UsesServo(rig, model)) {
    const bool limited = ModelValues(rig, model, {"/Servo/CurrentLimit"})[0] > 0.0;
    parameters = limited ? kCurrentLimitedServoBase : kServoBase;
  }
  for (const EffectDescription* effect : EnabledEffects(rig, model)) {
    parameters.insert(parameters.end(), effect->parameters.begin(), effect->parameters.end());
  }
  std::vector<std::string> paths;
  for (const FitParameter& parameter : parameters) paths.push_back(parameter.path);
  const std::vector<double> start = ModelValues(rig, model, paths);
  for (std::size_t i = 0; i < parameters.size(); ++i) parameters[i].start = start[i];
  return parameters;
}

namespace {

// The runs fitted on and the runs scored on: the last fitted run is held out when none is given; a single run
// serves as both (recorded as holdout_in_sample).
void SplitRuns(const std::vector<ReplayRun>& fit_given, const std::vector<ReplayRun>& holdout_given,
               std::vector<ReplayRun>& fit, std::vector<ReplayRun>& holdout, Diagnosis& d) {
  fit = fit_given;
  holdout = holdout_given;
  if (holdout.empty() && fit.size() >= 2) {
    holdout.push_back(fit.back());
    fit.pop_back();
  } else if (holdout.empty()) {
    holdout = fit;
    d.holdout_in_sample = true;
  }
  for (const ReplayRun& run : fit) d.fit_runs.push_back(run.source);
  for (const ReplayRun& run : holdout) d.holdout_runs.push_back(run.source);
}

// The coarse scan before an effect's fit (docs/gap.md, "How a fit works"): its main (first) parameter at
// kScanPoints points spread over its whole range, the others at their starts, one batch of replays. A swarm
// started weak finds a nearby local minimum (a 2° backlash fitted as 0.3°); the scan puts it in the right basin.
constexpr int kScanPoints = 9;

// The relaxed scan (--relax-scan, orcs-gap's default on the pendulum rig): the scan judges each value at the others'
// refit values, which belong to a model without the effect. So its best point and that point's neighbours first
// relax the others (Levenberg–Marquardt steps, all at once), and the main parameter's value that relaxes best
// starts the fit. A hidden 4° backlash on the servo model scans worst at 3.85° (0.52 deg², against 0.22 at 2.37°);
// relaxed, 3.85° comes to 0.06 deg² and 2.37° to 0.17. A relaxation only has to find the basin: 5 steps find that
// one as 15 did, at fewer replays, and leave the XL330 fits where the unrelaxed scan puts them (15 moved the kp100
// fit into another basin, docs/gap.md). Off for the A-Series: its relaxations' replays, which run to their end,
// would take its example past the 10 minutes it has.
constexpr int kRelaxIterations = 5;

struct ScanPoint {
  std::vector<double> values;  // one per parameter, in its unit
  double mse = 0.0;            // its fit objective, deg²
};

// Each point with the other parameters relaxed; its main parameter moves too.
void Relax(const ReplayObjective& objective, const std::vector<FitParameter>& parameters,
           std::vector<ScanPoint>& points) {
  std::vector<std::future<PolishOutcome>> polishes;  // at once, so that their Jacobians share the workers
  for (const ScanPoint& point : points) {
    polishes.push_back(std::async(std::launch::async, [&objective, &parameters, &point] {
      // No line search: each of its steps costs a Jacobian, and a relaxation only has to find the basin.
      return PolishLeastSquares(objective, parameters, point.values,
                                {.iterations = kRelaxIterations, .intervals = false, .line_search = false});
    }));
  }
  for (std::size_t k = 0; k < points.size(); ++k) {
    const PolishOutcome relaxed = polishes[k].get();
    if (relaxed.improved && relaxed.mse < points[k].mse) points[k] = {relaxed.values, relaxed.mse};
  }
}

// Returns the scan's points (relaxed where they were) as starts for the fit's local stages (FitOptions::starts).
// `given`: the base parameters' values in the model as given. The refit can take up an effect's signature in the
// wrong way (a heavier arm's sway in the accelerometers as a weaker torque limit), so the scan is repeated with the
// base at the model's values, and those points are starts for the local stages too.
std::vector<FitStart> ScanMainParameter(ReplayEvaluator& replays, const std::vector<ReplayRun>& fit,
                                        const std::vector<Override>& enabled, std::vector<FitParameter>& parameters,
                                        std::size_t main, bool relax, Loss loss, const std::vector<double>& given) {
  std::vector<ScanPoint> scan;
  for (int k = 0; k < kScanPoints; ++k) {
    ScanPoint& point = scan.emplace_back();
    for (const FitParameter& p : parameters) point.values.push_back(p.start);
    point.values[main] = FromUnit(parameters[main], (k + 0.5) / kScanPoints);
  }
  ScanPoint& weak = scan.emplace_back();  // the weak start competes too
  for (const FitParameter& p : parameters) weak.values.push_back(p.start);
  std::vector<ScanPoint> scan_given;
  if (!std::equal(given.begin(), given.end(), scan.front().values.begin())) {
    for (int k = 0; k < kScanPoints; ++k) {
      ScanPoint& point = scan_given.emplace_back(scan[static_cast<std::size_t>(k)]);
      std::copy(given.begin(), given.end(), point.values.begin());
    }
  }
  std::vector<std::vector<Override>> points;
  for (const ScanPoint& point : scan) points.push_back(OverridesOf(parameters, point.values));
  for (const ScanPoint& point : scan_given) points.push_back(OverridesOf(parameters, point.values));
  const ReplayObjective objective(replays, fit, enabled, loss);
  const std::vector<double> errors = objective.Losses(points);
  for (std::size_t k = 0; k < scan.size(); ++k) scan[k].mse = errors[k];
  for (std::size_t k = 0; k < scan_given.size(); ++k) scan_given[k].mse = errors[scan.size() + k];

  std::vector<FitStart> starts;
  for (const ScanPoint& point : scan_given) starts.push_back({point.values, point.mse});
  if (!relax) {
    parameters[main].start = scan[static_cast<std::size_t>(std::min_element(errors.begin(), errors.begin() + scan.size()) -
                                                           errors.begin())].values[main];
    for (const ScanPoint& point : scan) starts.push_back({point.values, point.mse});
    return starts;
  }
  const std::size_t best = static_cast<std::size_t>(
      std::min_element(errors.begin(), errors.begin() + kScanPoints) - errors.begin());
  std::vector<ScanPoint> bracket;
  for (std::size_t k = best == 0 ? 0 : best - 1; k <= std::min<std::size_t>(best + 1, kScanPoints - 1); ++k) {
    bracket.push_back(scan[k]);
  }
  if (scan.back().mse < scan[best].mse) bracket.push_back(scan.back());
  Relax(objective, parameters, bracket);
  const auto relaxed_best = std::min_element(bracket.begin(), bracket.end(),
                                             [](const ScanPoint& a, const ScanPoint& b) { return a.mse < b.mse; });
  // Only the main parameter's value: the swarm starts from the others' refit values as before. Started from the
  // relaxed point itself, the fit of a hidden Stribeck friction stopped in a local minimum nearby. The relaxed
  // points themselves are starts for the local stages.
  parameters[main].start = relaxed_best->values[main];
  for (const ScanPoint& point : scan) starts.push_back({point.values, point.mse});
  for (const ScanPoint& point : bracket) starts.push_back({point.values, point.mse});
  return starts;
}

// The race's board (docs/gap.md, "How a fit works"): each candidate posts its penalised held-out score after its
// race polish and waits until every candidate has posted (or ended), so that each is judged against the best of all,
// whatever order they arrived in: the diagnosis stays the same bit for bit.
class RaceBoard {
 public:
  explicit RaceBoard(std::size_t candidates) : missing_(candidates) {}

  // What a candidate is compared with: the lowest posted held-out score, and the fit error of the candidate that
  // posted it.
  struct Leader {
    double score = std::numeric_limits<double>::infinity();
    double fit_mse = std::numeric_limits<double>::infinity();
  };

  // One candidate's place on the board, used from that candidate's thread. A candidate that ends without having
  // posted (it threw, or its swarm is shorter than the race) posts +∞ when its entry goes, so that no other waits
  // for it.
  class Entry {
   public:
    explicit Entry(RaceBoard* board) : board_(board) {}
    Entry(const Entry&) = delete;
    Entry& operator=(const Entry&) = delete;
    ~Entry() {
      if (board_ != nullptr && !posted_) board_->Post({});
    }
    // Posts a held-out score and its fit error; returns the leader once every candidate has posted.
    Leader PostAndWaitForAll(double score, double fit_mse) {
      posted_ = true;
      return board_->PostAndWait({score, fit_mse});
    }

   private:
    RaceBoard* board_;
    bool posted_ = false;
  };

 private:
  void Post(const Leader& posted) {
    std::lock_guard lock(mutex_);
    Record(posted);
  }
  Leader PostAndWait(const Leader& posted) {
    std::unique_lock lock(mutex_);
    Record(posted);
    everyone_.wait(lock, [this] { return missing_ == 0; });
    return best_;
  }
  void Record(const Leader& posted) {
    // Ties in score go to the lower fit error, so that the leader does not depend on the order of posting.
    if (posted.score < best_.score || (posted.score == best_.score && posted.fit_mse < best_.fit_mse)) best_ = posted;
    if (missing_ > 0) --missing_;
    everyone_.notify_all();
  }

  std::mutex mutex_;
  std::condition_variable everyone_;
  std::size_t missing_;                                   // candidates still to post
  Leader best_;                                           // the lowest posted score and its fit error
};

// LinkMass (a per-link effect): which link. Each link's mass at kLinkFactors of the model's, the base parameters at
// the refit's values, as one batch; the link of the best point, its mass the parameter (a quarter to four times the
// model's, started at the best factor). `summary` says which link it is.
constexpr double kLinkFactors[] = {0.5, 1.5, 3.0};

FitParameter ChooseLink(ReplayEvaluator& replays, const Rig& rig, const std::vector<ValueAssignment>& model,
                        const std::vector<ReplayRun>& fit, const std::vector<FitParameter>& refitted,
                        const std::vector<double>& given, Loss loss, std::string& summary,
                        std::vector<FitStart>& starts) {
  std::vector<std::string> paths;
  for (const std::string& link : rig.links) paths.push_back("/Sim/" + rig.agent + "/" + link + "/Mass");
  const std::vector<double> masses = ModelValues(rig, model, paths);
  std::vector<double> refit_values;
  for (const FitParameter& p : refitted) refit_values.push_back(p.start);
  const std::vector<const std::vector<double>*> bases = {&refit_values, &given};
  struct Tried {
    std::size_t link;
    double factor;
    const std::vector<double>* base;
  };
  std::vector<std::vector<Override>> points;
  std::vector<Tried> tried;
  for (const std::vector<double>* base : bases) {
    for (std::size_t l = 0; l < rig.links.size(); ++l) {
      if (!(masses[l] > 0.0)) continue;
      for (double factor : kLinkFactors) {
        std::vector<Override> point = OverridesOf(refitted, *base);
        point.emplace_back(paths[l], text::FormatDouble(masses[l] * factor));
        points.push_back(std::move(point));
        tried.push_back({l, factor, base});
      }
    }
  }
  if (points.empty()) throw InputError(rig.environment_name + ": LinkMass: agent '" + rig.agent + "' has no link with a mass");
  const std::vector<double> losses = ReplayObjective(replays, fit, {}, loss).Losses(points);
  const std::size_t best = static_cast<std::size_t>(std::min_element(losses.begin(), losses.end()) - losses.begin());
  const Tried& chosen = tried[best];
  summary = rig.links[chosen.link];
  const double mass = masses[chosen.link] * chosen.factor;
  // The best point of either base, as a start for the local stages.
  for (const std::vector<double>* base : bases) {
    double lowest = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < tried.size(); ++k) {
      if (tried[k].link == chosen.link && tried[k].base == base) lowest = std::min(lowest, losses[k]);
    }
    for (std::size_t k = 0; k < tried.size(); ++k) {
      if (tried[k].link != chosen.link || tried[k].base != base || losses[k] != lowest) continue;
      std::vector<double> values = *base;
      values.push_back(masses[chosen.link] * tried[k].factor);
      starts.push_back({std::move(values), losses[k]});
      break;
    }
  }
  return {paths[chosen.link], "kg", masses[chosen.link] / 4.0, masses[chosen.link] * 4.0, true, mass};
}

// The effect's own parameters (from `first_added` on) that the fit runs leave open, probed across their intervals
// (open_parameter_probe.h): the score moves to the point the held-out runs choose among those that fit the fit runs
// within the tie's ratio. The base parameters are the refit's business, not the candidate's.
void ProbeOpen(ReplayEvaluator& replays, const std::vector<ReplayRun>& fit, const std::vector<ReplayRun>& holdout,
               const std::vector<FitParameter>& parameters, const std::vector<Override>& enabled,
               std::size_t first_added, Loss loss, ModelScore& score) {
  std::vector<double> values, ci95;
  std::vector<bool> identified;
  for (const FittedValue& value : score.values) {
    values.push_back(value.value);
    ci95.push_back(value.ci95);
    identified.push_back(value.identified);
  }
  const OpenProbeResult probed = ProbeOpenParameters(replays, fit, holdout, parameters, enabled, first_added, values,
                                                     ci95, identified, score.fit.mse, score.holdout_loss,
                                                     {loss, kTieRatio});
  score.open = probed.open;
  if (probed.values == values) return;
  for (std::size_t i = 0; i < values.size(); ++i) score.values[i].value = probed.values[i];
  score.holdout_loss = probed.holdout_loss;
  if (loss == Loss::kSquared) {
    score.fit_rms = Rms(probed.fit_loss);
    score.holdout_rms = Rms(probed.holdout_loss);
    return;
  }
  std::vector<Override> model = enabled;
  const std::vector<Override> point = OverridesOf(parameters, probed.values);
  model.insert(model.end(), point.begin(), point.end());
  score.fit_rms = Rms(MeanSquaredError(replays, fit, model));
  score.holdout_rms = Rms(MeanSquaredError(replays, holdout, model));
}

// One candidate effect fitted together with the (refitted) base parameters, scored with its penalty.
ModelScore ScoreCandidate(ReplayEvaluator& replays, const Rig& rig, const std::vector<ValueAssignment>& model,
                          const std::vector<ReplayRun>& fit, const std::vector<ReplayRun>& holdout,
                          const std::vector<FitParameter>& refitted, const std::vector<double>& given,
                          const ModelScore& refit, const EffectDescription& effect, const DiagnosisOptions& options,
                          RaceBoard* board) {
  // A candidate that ends without posting to the race's board (it threw, or its swarm is shorter than the race)
  // posts when it ends, so that no other waits for it.
  RaceBoard::Entry entry(board);
  std::vector<FitParameter> parameters = refitted;
  std::string summary(effect.summary);
  if (options.on_fit) options.on_fit(std::string(effect.name), nullptr);
  std::vector<FitStart> link_starts;
  if (effect.per_link) {
    parameters.push_back(ChooseLink(replays, rig, model, fit, refitted, given, options.loss, summary, link_starts));
  }
  for (FitParameter p : effect.parameters) {
    // Effects start weak: the geometric middle between the bottom of the range and its middle.
    p.start = std::sqrt(p.lower * std::sqrt(p.lower * p.upper));
    parameters.push_back(std::move(p));
  }
  std::vector<Override> enabled;
  if (effect.switched) enabled.emplace_back(EnabledPath(effect), "T");
  FitOptions fit_options = options.fit;
  fit_options.starts = ScanMainParameter(replays, fit, enabled, parameters, refitted.size(), options.relax_scan,
                                         options.loss, given);
  fit_options.starts.insert(fit_options.starts.end(), link_starts.begin(), link_starts.end());
  const int added = static_cast<int>(parameters.size() - refitted.size());
  const auto penalised = [&](double holdout_loss) {
    return holdout_loss * (1.0 + options.penalty_per_parameter * added);
  };
  std::string race;  // what the race saw
  if (board != nullptr) {
    // The race (docs/gap.md, "How a fit works"), of the candidate's point polished after 10 generations of its swarm:
    // it is abandoned when its held-out score is far behind the best any candidate has then (every candidate posts
    // its score to the board, and each waits for all, so that the verdict does not depend on which came first), or
    // when it is no better than nothing missing on either count: a candidate stays when it fits the fit runs clearly
    // better than the refit, or scores no worse on the held-out runs. Either alone loses effects: mid-fit, a
    // Stribeck fit is far ahead on the fit runs and still behind on the held-out ones.
    fit_options.abandon = [&](const std::vector<double>& values, double mse) -> std::string {
      std::vector<Override> candidate = enabled;
      const std::vector<Override> point = OverridesOf(parameters, values);
      candidate.insert(candidate.end(), point.begin(), point.end());
      const double held = penalised(LossOf(replays, holdout, candidate, options.loss));
      const RaceBoard::Leader leader = entry.PostAndWaitForAll(held, mse);
      race = "penalised held-out score " + text::FormatDouble(held) + ", " +
             text::FormatDouble(std::round(held / leader.score * 100.0) / 100.0) + " times the best candidate's, " +
             Percent(held / refit.score) + " of nothing missing's; fit error " + Percent(mse / refit.fit.mse) +
             " of the refit's";
      if (!(refit.score > 0.0) || !(refit.fit.mse > 0.0)) return "";  // a perfect refit: nothing to race against
      // Far behind the leader held out, and fitting the fit runs no better than the leader does. A candidate that
      // fits them better stays: its swarm may not have found the basin that also fits the held-out runs yet (a
      // hidden LuGre friction on the pendulum, at the noise on the fit run and 4.2° held out at that point).
      if (held > kRaceLeaderRatio * leader.score && mse >= leader.fit_mse) {
        return "its penalised held-out score was " + text::FormatDouble(std::round(held / leader.score * 10.0) / 10.0) +
               " times the best candidate's at that point (limit " + text::FormatDouble(kRaceLeaderRatio) +
               "), and it fitted the fit runs no better";
      }
      const double fit_share = mse / refit.fit.mse;
      const double share = held / refit.score;
      if (fit_share <= kRaceFitShare || share <= options.abandon_share) return "";
      return "its fit error was " + Percent(fit_share) + " of the refit's (limit " + Percent(kRaceFitShare) +
             ") and its penalised held-out score " + Percent(share) + " (limit " + Percent(options.abandon_share) + ")";
    };
  }
  ModelScore score = ScoreFit(replays, fit, holdout, parameters, enabled, fit_options, options.loss);
  if (!score.fit.abandoned) ProbeOpen(replays, fit, holdout, parameters, enabled, refitted.size(), options.loss, score);
  score.label = std::string(effect.name);
  score.summary = summary;
  score.race = race;
  if (effect.per_link) {
    const double fitted = score.values.back().value;
    const double nominal = ModelValues(rig, model, {score.values.back().path})[0];
    score.summary = "the mass of " + summary + " is " + text::FormatDouble(std::round(fitted * 1e4) / 1e4) +
                    " kg, not the model's " + text::FormatDouble(nominal) + " kg";
  }
  score.quantity = std::string(effect.quantity);
  score.added_parameters = added;
  score.score = penalised(score.holdout_loss);
  if (options.on_fit) options.on_fit(score.label, &score);
  return score;
}

// Every candidate effect, fitted with the base parameters started from the refit, all at once; best first.
std::vector<ModelScore> ScoreCandidates(ReplayEvaluator& replays, const Rig& rig,
                                        const std::vector<ValueAssignment>& model, const std::vector<ReplayRun>& fit,
                                        const std::vector<ReplayRun>& holdout, const std::vector<FitParameter>& base,
                                        const ModelScore& refit, const DiagnosisOptions& options,
                                        const std::vector<const EffectDescription*>& candidates) {
  std::vector<FitParameter> refitted = base;
  std::vector<double> given;  // the base parameters' values in the model as given
  for (std::size_t i = 0; i < base.size(); ++i) {
    refitted[i].start = refit.fit.values[i];
    given.push_back(base[i].start);
  }
  std::unique_ptr<RaceBoard> board;
  if (std::isfinite(options.abandon_share)) board = std::make_unique<RaceBoard>(candidates.size());
  std::vector<std::future<ModelScore>> fits;
  for (const EffectDescription* effect : candidates) {
    fits.push_back(std::async(std::launch::async, [&, effect] {
      return ScoreCandidate(replays, rig, model, fit, holdout, refitted, given, refit, *effect, options, board.get());
    }));
  }
  std::vector<ModelScore> scores;
  for (auto& future : fits) scores.push_back(future.get());
  std::stable_sort(scores.begin(), scores.end(), [](const ModelScore& a, const ModelScore& b) { return a.score < b.score; });
  return scores;
}

}  // namespace

Diagnosis Diagnose(ReplayEvaluator& replays, const Rig& rig, const std::vector<ReplayRun>& fit_given,
                   const std::vector<ReplayRun>& holdout_given, const std::vector<ValueAssignment>& model,
                   const DiagnosisOptions& options) {
  const auto started = std::chrono::steady_clock::now();
  const std::uint64_t replays_before = replays.replays_run();
  const std::uint64_t stopped_before = replays.replays_stopped_early();
  Diagnosis d;
  std::vector<ReplayRun> fit, holdout;
  SplitRuns(fit_given, holdout_given, fit, holdout, d);
  const std::vector<const EffectDescription*> candidates =
      Candidates(options.candidates, UsesServo(rig, model), EnabledEffects(rig, model), HasAccelerometers(fit_given));

  // 1. The model as given.
  d.before = Snapshot(replays, fit, holdout, {}, rig.step, /*record=*/true);

  // 2. Its own parameters refitted.
  const std::vector<FitParameter> base = BaseParameters(rig, model);
  if (options.on_fit) options.on_fit("refit", nullptr);
  FitOptions refit_options = options.fit;
  refit_options.least_change = true;  // its starts are the model's values: of minima that fit alike, the nearer
  d.base = ScoreFit(replays, fit, holdout, base, {}, refit_options, options.loss);
  d.base.label = "refit";
  // "Nothing missing" is the refit or the model as given, whichever scores better held out: a refit can take up
  // a missing effect's signature in the wrong way and generalise worse than the model it started from.
  d.base.score = std::min(d.base.holdout_loss, LossOf(replays, holdout, {}, options.loss));
  if (options.on_fit) options.on_fit("refit", &d.base);

  // 3. Every candidate effect.
  d.candidates = ScoreCandidates(replays, rig, model, fit, holdout, base, d.base, options, candidates);

  // 4. The verdict — the winner, and any candidate the held-out runs cannot tell from it — and the gap of the
  // model it leaves.
  const bool won = !d.candidates.empty() && d.candidates[0].score < options.win_ratio * d.base.score;
  if (won) {
    NameEffects(options, d);
    if (d.effects.size() > 1) d.tell_apart = BestProbe(replays, rig, model, fit, d);
    PinDownOpenParameters(replays, rig, model, fit, d);
  }
  d.quantity = won ? ScoreOf(d, d.effect).quantity : "speed";
  d.model_values = won ? ModelOf(ScoreOf(d, d.effect), d.effect) : ModelOf(d.base, "");
  // The fitted model's replays are recorded for replays/<run>.orcsrec: the winner's, else the refit's.
  d.refit = Snapshot(replays, fit, holdout, ModelOf(d.base, ""), rig.step, /*record=*/!won);
  d.after = won ? Snapshot(replays, fit, holdout, d.model_values, rig.step, /*record=*/true) : d.refit;
  d.verdict = Verdict(d, options);
  d.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  d.jobs = replays.replays_run() - replays_before;
  d.jobs_stopped_early = replays.replays_stopped_early() - stopped_before;
  return d;
}

}  // namespace orcs::identify
