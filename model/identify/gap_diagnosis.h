// The gap workflow (docs/gap.md): replay the measured runs under the current model, refit the model's own
// parameters, then try every effect of the catalogue (model/identify/effect_catalogue.h) — each fitted together with
// the base parameters, each scored on held-out runs with a penalty per added parameter — and name the winner only
// when it clearly beats "nothing missing".
#pragma once

#include <functional>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "model/identify/gap_statistics.h"
#include "model/identify/model_fit.h"
#include "model/identify/open_parameter_probe.h"
#include "model/identify/probe_comparison.h"
#include "model/identify/replay.h"
#include "model/identify/replay_evaluator.h"

namespace orcs::identify {

struct ModelScore;

/// A candidate whose held-out RMS is within this factor of the winner's explains the held-out runs as well, within
/// the noise: since the winner's RMS is at least the noise, the rest is less than half the noise in quadrature
/// (√(1.118² − 1) = 0.5). The verdict names both (docs/gap.md, "When two effects explain the data"). With the
/// absolute loss, the factor applies to the mean absolute errors.
inline constexpr double kTieRatio = 1.118;

inline constexpr double kRaceAbandonShare = 1.0;  ///< abandoned when no better than "nothing missing"...
inline constexpr double kRaceFitShare = 0.8;      ///< ...and its fit error above this share of the refit's
/// ...or when its penalised held-out score is more than this many times the best any candidate has at the race (its
/// held-out RMS twice the leader's, far beyond a tie: kTieRatio) while it fits the fit runs no better than that leader
inline constexpr double kRaceLeaderRatio = 4.0;

struct DiagnosisOptions {
  FitOptions fit;                        ///< optimiser budget and seed of every fit
  std::vector<std::string> candidates;   ///< effect names to try; empty = the whole catalogue
  double penalty_per_parameter = 0.05;   ///< the score grows by this share per parameter an effect adds
  double win_ratio = 0.5;                ///< a winner's score must be below this share of "nothing missing"'s
  /// The fits' objective and the held-out scores' measure (orcs-gap --loss): the mean squared angle error (deg²)
  /// or the mean absolute one (deg; docs/gap.md, "How a fit works").
  Loss loss = Loss::kSquared;
  /// The race (orcs-gap's default sets kRaceAbandonShare): after FitOptions::abandon_after swarm generations a
  /// candidate whose best point so far has a fit error above kRaceFitShare of the refit's and a penalised
  /// held-out score above this share of the refit's is abandoned; the diagnosis spends its replays on the others.
  /// Infinite = never (--no-race).
  double abandon_share = std::numeric_limits<double>::infinity();
  /// After each effect's scan, the scan's best point and its neighbours relax the other parameters (Levenberg–
  /// Marquardt) before the main parameter's start is chosen (--relax-scan, orcs-gap's default on the pendulum rig;
  /// docs/gap.md, "How a fit works"). Finds basins the scan misjudges at the refit's values; costs up to three
  /// short polishes per candidate.
  bool relax_scan = false;
  /// Told when a fit starts (`finished` null; `model` is "refit" or the effect's name) and when it ends (its
  /// score), for progress. Candidates are fitted at once: it is called from several threads.
  std::function<void(const std::string& model, const ModelScore* finished)> on_fit;
  /// The `orcs-gap synth` command of this rig ("orcs-gap synth --rig pendulum"), for the verdict's advice on how to
  /// make the motion that tells two tied effects apart; "" = "orcs-gap synth".
  std::string synth_command;
};

/// A fitted parameter as reported.
struct FittedValue {
  std::string path;
  std::string unit;
  double start = 0.0;  ///< where the fit started
  double value = 0.0;  ///< where it ended
  double ci95 = std::numeric_limits<double>::quiet_NaN();  ///< 95 % half-width in the unit; NaN = not determined
  bool identified = false;  ///< the data determine it: a finite interval narrower than the value (Identified)
  BoundState bound = BoundState::kInside;  ///< where it ended against its range (FitOutcome::bounds)
};

/// One model's fit and scores.
struct ModelScore {
  std::string label;                  ///< "refit" or the effect's name
  std::string summary;                ///< the effect's one-line description ("" for refit)
  std::string quantity;               ///< the effect's signature quantity
  std::vector<FittedValue> values;    ///< every fitted parameter (base ones first)
  int added_parameters = 0;           ///< parameters beyond the base ones
  double fit_rms = 0.0;               ///< degrees, pooled over the fit runs
  double holdout_rms = 0.0;           ///< degrees, pooled over the held-out runs
  double holdout_loss = 0.0;          ///< the loss over the held-out runs: holdout_rms² (deg²), or the mean
                                      ///< absolute error (deg) with Loss::kAbsolute
  double score = 0.0;                 ///< holdout_loss · (1 + penalty · added_parameters)
  FitOutcome fit;                     ///< budget, convergence
  /// What the race saw of it after its swarm's first generations (its polished point's penalised held-out score
  /// against the best candidate's and nothing missing's, its fit error against the refit's); "" without a race
  std::string race;
  /// The effect's own parameters the fit runs leave open, as probed (open_parameter_probe.h); `values`, the losses
  /// and the score are those of the point the probes kept
  std::vector<OpenParameter> open;
};

/// A candidate beside the winner that the held-out runs cannot tell from it (docs/gap.md, "When two effects
/// explain the data"): its held-out RMS is within kTieRatio of the winner's.
struct Rival {
  std::string effect;            ///< its name
  double ratio = 1.0;            ///< its held-out RMS (mean absolute error with the absolute loss) over the named one's
  std::string relation;          ///< how the two relate (EffectRelation::text), "" when the catalogue says nothing
  /// It contains the named effect exactly (EffectRelation::nested) and fits no better: the simpler is named alone
  /// and this one is said to add nothing the data need. Otherwise it is named beside the winner: a tie.
  bool contains_named = false;
};

/// One run's gap under one model version.
struct RunGap {
  std::string run;                  ///< the run's name
  bool held_out = false;            ///< scored, not fitted
  double rms = 0.0;                 ///< degrees, over its channels' samples (NaN when its replay failed)
  double mean_absolute_mrad = 0.0;  ///< mean absolute position error, mrad: the BAM project's metric
};

/// The gap of one model version, with the channel statistics over all runs (fit and holdout).
struct GapSnapshot {
  double fit_rms = 0.0;      ///< degrees
  double holdout_rms = 0.0;  ///< degrees
  std::vector<ChannelStatistics> channels;  ///< per run and motor ("run:motor"), worst first
  std::vector<RunGap> runs;                 ///< per run, fit runs first
  std::vector<std::vector<ChannelTrace>> traces;  ///< per run (fit runs, then holdout runs): the channels' traces
  /// run name → its replay's recording (docs/recording.md), for the snapshots orcs-gap writes to replays/: the
  /// model as given (before) and the fitted model (after); empty for the others
  std::map<std::string, std::string> recordings;
};

struct Diagnosis {
  std::vector<std::string> fit_runs;      ///< files
  std::vector<std::string> holdout_runs;  ///< files
  bool holdout_in_sample = false;         ///< no run could be held out: holdout scores are the fit runs'
  GapSnapshot before;                     ///< the model as given
  GapSnapshot refit;                      ///< base parameters refitted
  GapSnapshot after;                      ///< with the winning effect (== refit when none won)
  ModelScore base;                        ///< the refit
  std::vector<ModelScore> candidates;     ///< every effect tried, best score first
  std::string effect;                     ///< the winner, "" = no missing effect found
  std::vector<std::string> effects;       ///< every effect named: the winner, then those tied with it
  std::vector<Rival> rivals;              ///< candidates the held-out runs cannot tell from the winner
  TellApart tell_apart;                   ///< for a tie: the motion that tells the first two apart (probe "" = none)
  std::string verdict;                    ///< one paragraph
  std::string quantity;                   ///< the quantity its residual is plotted against ("speed" when none)
  std::vector<Override> model_values;     ///< the fitted model: refit base values, winner's switch and values
  double seconds = 0.0;                   ///< wall clock
  std::uint64_t jobs = 0;                 ///< replays run (in orcs-gap each is one job)
  std::uint64_t jobs_stopped_early = 0;   ///< of those, stopped where their point could not beat the search's best
};

/// Runs the whole workflow. `holdout` may be empty: then the last fit run is held out (when there are two or
/// more), else scores are in-sample. Throws InputError for unknown candidate names.
Diagnosis Diagnose(ReplayEvaluator& replays, const Rig& rig, const std::vector<ReplayRun>& fit,
                   const std::vector<ReplayRun>& holdout, const std::vector<ValueAssignment>& model,
                   const DiagnosisOptions& options);

/// The base parameters every diagnosis refits first, with the model's values as start: the motor model's own
/// (the physical servo's with R in place of kt and ke when the model sets a current limit), then the parameters of
/// every catalogue effect the model switches on — a second pass with the first's model.val refits what the first
/// found, and that effect is no longer a candidate.
std::vector<FitParameter> BaseParameters(const Rig& rig, const std::vector<ValueAssignment>& model);

struct EffectDescription;
/// The catalogue's effects that the model switches on (/Effects/<name>/Enabled), in catalogue order.
std::vector<const EffectDescription*> EnabledEffects(const Rig& rig, const std::vector<ValueAssignment>& model);

}  // namespace orcs::identify
