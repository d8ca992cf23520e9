#include "model/identify/gap_diagnosis.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <future>
#include <sstream>

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
    report.push_back({parameters[i].path, parameters[i].unit, parameters[i].start, fit.values[i], ci95,
                      Identified(fit.values[i], ci95)});
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
  if (!effect.empty()) model.emplace_back("/Effects/" + effect + "/Enabled", "T");
  for (const FittedValue& value : score.values) model.emplace_back(value.path, text::FormatDouble(value.value));
  return model;
}

// The effects to try: the named ones, or the catalogue's defaults for the motor model (`servo`: the physical
// servo's). An effect the model switches on already is part of the base (BaseParameters), not a candidate.
std::vector<const EffectDescription*> Candidates(const std::vector<std::string>& names, bool servo,
                                                 const std::vector<const EffectDescription*>& enabled) {
  const auto in_model = [&enabled](const EffectDescription* effect) {
    return std::find(enabled.begin(), enabled.end(), effect) != enabled.end();
  };
  std::vector<const EffectDescription*> candidates;
  if (names.empty()) {
    for (const EffectDescription& effect : EffectCatalogue()) {
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

std::string Percent(double fraction) { return text::FormatDouble(std::round(fraction * 1000.0) / 10.0) + " %"; }
std::string Degrees(double value) { return text::FormatDouble(std::round(value * 1000.0) / 1000.0) + "°"; }

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
  const ModelScore& winner = d.candidates[0];
  text << "Missing effect: " << d.effect << " (" << winner.summary << "). With it the held-out gap falls from "
       << Degrees(d.before.holdout_rms) << " (model as given) and " << Degrees(d.base.holdout_rms)
       << " (base parameters refitted) to " << Degrees(winner.holdout_rms) << " RMS; its penalised score is "
       << Percent(winner.score / base) << " of \"nothing missing\"";
  if (d.candidates.size() > 1) {
    text << ", the runner-up " << d.candidates[1].label << " reaches " << Percent(d.candidates[1].score / base);
  }
  text << ".";
  return text.str();
}

}  // namespace

std::vector<const EffectDescription*> EnabledEffects(const Rig& rig, const std::vector<ValueAssignment>& model) {
  std::vector<std::string> paths;
  for (const EffectDescription& effect : EffectCatalogue()) paths.push_back(EnabledPath(effect));
  const std::vector<bool> on = ModelSwitches(rig, model, paths);
  std::vector<const EffectDescription*> enabled;
  for (std::size_t i = 0; i < on.size(); ++i) {
    if (on[i]) enabled.push_back(&EffectCatalogue()[i]);
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

void ScanMainParameter(ReplayEvaluator& replays, const std::vector<ReplayRun>& fit, const std::vector<Override>& enabled,
                       std::vector<FitParameter>& parameters, std::size_t main, bool relax, Loss loss) {
  std::vector<ScanPoint> scan;
  for (int k = 0; k < kScanPoints; ++k) {
    ScanPoint& point = scan.emplace_back();
    for (const FitParameter& p : parameters) point.values.push_back(p.start);
    point.values[main] = FromUnit(parameters[main], (k + 0.5) / kScanPoints);
  }
  ScanPoint& weak = scan.emplace_back();  // the weak start competes too
  for (const FitParameter& p : parameters) weak.values.push_back(p.start);
  std::vector<std::vector<Override>> points;
  for (const ScanPoint& point : scan) points.push_back(OverridesOf(parameters, point.values));
  const ReplayObjective objective(replays, fit, enabled, loss);
  const std::vector<double> errors = objective.Losses(points);
  for (std::size_t k = 0; k < scan.size(); ++k) scan[k].mse = errors[k];

  if (!relax) {
    parameters[main].start = scan[static_cast<std::size_t>(std::min_element(errors.begin(), errors.end()) -
                                                           errors.begin())].values[main];
    return;
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
  // relaxed point itself, the fit of a hidden Stribeck friction stopped in a local minimum nearby.
  parameters[main].start = relaxed_best->values[main];
}

// One candidate effect fitted together with the (refitted) base parameters, scored with its penalty.
ModelScore ScoreCandidate(ReplayEvaluator& replays, const std::vector<ReplayRun>& fit, const std::vector<ReplayRun>& holdout,
                          const std::vector<FitParameter>& refitted, const ModelScore& refit, const EffectDescription& effect,
                          const DiagnosisOptions& options) {
  std::vector<FitParameter> parameters = refitted;
  for (FitParameter p : effect.parameters) {
    // Effects start weak: the geometric middle between the bottom of the range and its middle.
    p.start = std::sqrt(p.lower * std::sqrt(p.lower * p.upper));
    parameters.push_back(std::move(p));
  }
  const std::vector<Override> enabled{{EnabledPath(effect), "T"}};
  if (options.on_fit) options.on_fit(std::string(effect.name), nullptr);
  ScanMainParameter(replays, fit, enabled, parameters, refitted.size(), options.relax_scan, options.loss);
  const int added = static_cast<int>(effect.parameters.size());
  const auto penalised = [&](double holdout_loss) {
    return holdout_loss * (1.0 + options.penalty_per_parameter * added);
  };
  FitOptions fit_options = options.fit;
  if (std::isfinite(options.abandon_share)) {
    // A candidate stays in the race when its best point so far already fits the fit runs clearly better than the
    // refit, or scores no worse on the held-out runs (the selection criterion itself). Either alone loses effects:
    // mid-fit, a Stribeck fit is far ahead on the fit runs and still behind on the held-out ones.
    fit_options.abandon = [&](const std::vector<double>& values, double mse) -> std::string {
      if (!(refit.score > 0.0) || !(refit.fit.mse > 0.0)) return "";  // a perfect refit: nothing to race against
      const double fit_share = mse / refit.fit.mse;
      if (fit_share <= kRaceFitShare) return "";
      std::vector<Override> model = enabled;
      const std::vector<Override> point = OverridesOf(parameters, values);
      model.insert(model.end(), point.begin(), point.end());
      const double share = penalised(LossOf(replays, holdout, model, options.loss)) / refit.score;
      if (share <= options.abandon_share) return "";
      return "its fit error was " + Percent(fit_share) + " of the refit's (limit " + Percent(kRaceFitShare) +
             ") and its penalised held-out score " + Percent(share) + " (limit " + Percent(options.abandon_share) + ")";
    };
  }
  ModelScore score = ScoreFit(replays, fit, holdout, parameters, enabled, fit_options, options.loss);
  score.label = std::string(effect.name);
  score.summary = std::string(effect.summary);
  score.quantity = std::string(effect.quantity);
  score.added_parameters = added;
  score.score = penalised(score.holdout_loss);
  if (options.on_fit) options.on_fit(score.label, &score);
  return score;
}

// Every candidate effect, fitted with the base parameters started from the refit, all at once; best first.
std::vector<ModelScore> ScoreCandidates(ReplayEvaluator& replays, const std::vector<ReplayRun>& fit,
                                        const std::vector<ReplayRun>& holdout, const std::vector<FitParameter>& base,
                                        const ModelScore& refit, const DiagnosisOptions& options,
                                        const std::vector<const EffectDescription*>& candidates) {
  std::vector<FitParameter> refitted = base;
  for (std::size_t i = 0; i < base.size(); ++i) refitted[i].start = refit.fit.values[i];
  std::vector<std::future<ModelScore>> fits;
  for (const EffectDescription* effect : candidates) {
    fits.push_back(std::async(std::launch::async, [&, effect] {
      return ScoreCandidate(replays, fit, holdout, refitted, refit, *effect, options);
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
      Candidates(options.candidates, UsesServo(rig, model), EnabledEffects(rig, model));

  // 1. The model as given.
  d.before = Snapshot(replays, fit, holdout, {}, rig.step, /*record=*/true);

  // 2. Its own parameters refitted.
  const std::vector<FitParameter> base = BaseParameters(rig, model);
  if (options.on_fit) options.on_fit("refit", nullptr);
  d.base = ScoreFit(replays, fit, holdout, base, {}, options.fit, options.loss);
  d.base.label = "refit";
  d.base.score = d.base.holdout_loss;
  if (options.on_fit) options.on_fit("refit", &d.base);

  // 3. Every candidate effect.
  d.candidates = ScoreCandidates(replays, fit, holdout, base, d.base, options, candidates);

  // 4. The verdict, and the gap of the model it leaves.
  const bool won = !d.candidates.empty() && d.candidates[0].score < options.win_ratio * d.base.score;
  d.effect = won ? d.candidates[0].label : "";
  d.quantity = won ? d.candidates[0].quantity : "speed";
  d.model_values = won ? ModelOf(d.candidates[0], d.effect) : ModelOf(d.base, "");
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
