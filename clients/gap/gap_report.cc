#include "clients/gap/gap_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>
#include <filesystem>
#include <sstream>

#include "model/core/atomic_file.h"
#include "model/core/error.h"
#include "model/core/text.h"
#include "model/evaluation/recorder.h"

namespace orcs::gap {

using namespace identify;  // the analysis this command drives (model/identify/)
namespace {

namespace fs = std::filesystem;

nlohmann::json RoundedOrNull(double value) {
  if (!std::isfinite(value)) return nullptr;
  return value;
}

nlohmann::json ChannelsJson(const std::vector<ChannelStatistics>& channels) {
  nlohmann::json list = nlohmann::json::array();
  for (const ChannelStatistics& c : channels) {
    nlohmann::json regimes = nlohmann::json::object();
    for (const RegimeError& r : c.regimes) {
      regimes[r.regime] = {{"rms", RoundedOrNull(r.rms)}, {"share", r.share}, {"samples", r.samples}};
    }
    list.push_back({{"channel", c.name}, {"rms", RoundedOrNull(c.rms)}, {"max_abs", RoundedOrNull(c.max_abs)},
                    {"bias", RoundedOrNull(c.bias)}, {"best_shift_s", c.best_shift},
                    {"rms_at_best_shift", RoundedOrNull(c.rms_at_best_shift)}, {"regimes", regimes}});
  }
  return list;
}

nlohmann::json SnapshotJson(const GapSnapshot& s) {
  nlohmann::json runs = nlohmann::json::array();
  for (const RunGap& run : s.runs) {
    runs.push_back({{"run", run.run}, {"held_out", run.held_out}, {"rms", RoundedOrNull(run.rms)},
                    {"mean_absolute_mrad", RoundedOrNull(run.mean_absolute_mrad)}});
  }
  return {{"fit_rms", RoundedOrNull(s.fit_rms)},
          {"holdout_rms", RoundedOrNull(s.holdout_rms)},
          {"runs", runs},
          {"channels", ChannelsJson(s.channels)}};
}

// "12.3 mrad / 0.704°": the BAM project's metric beside orcs's.
std::string RunCell(const RunGap& run) {
  if (!std::isfinite(run.rms)) return "replay failed";
  return text::FormatDouble(std::round(run.mean_absolute_mrad * 10.0) / 10.0) + " mrad / " +
         text::FormatDouble(std::round(run.rms * 1000.0) / 1000.0) + "°";
}

// report.json's "bound" of a fitted value: null inside its range.
nlohmann::json BoundName(BoundState bound) {
  switch (bound) {
    case BoundState::kInside: return nullptr;
    case BoundState::kBeyond: return "beyond";
    case BoundState::kAtLower: return "lower";
    case BoundState::kAtUpper: return "upper";
  }
  return nullptr;
}

// report.md's note on a fitted value's bound ("" inside its range).
std::string BoundNote(BoundState bound) {
  switch (bound) {
    case BoundState::kInside: return "";
    case BoundState::kBeyond: return " (beyond the catalogue's range)";
    case BoundState::kAtLower: return " (at the bottom of its range)";
    case BoundState::kAtUpper: return " (at the top of its range)";
  }
  return "";
}

nlohmann::json TellApartJson(const TellApart& t) {
  if (t.probe.empty()) return nullptr;
  return {{"probe", t.probe}, {"motor", t.motor}, {"description", t.description}, {"shows", t.shows},
          {"difference_deg", t.difference}, {"noise_deg", t.noise}};
}

// The open parameters a candidate's probes tried (open_parameter_probe.h); losses in the loss's unit.
nlohmann::json OpenJson(const std::vector<OpenParameter>& open) {
  nlohmann::json probes = nlohmann::json::array();
  for (const OpenParameter& o : open) {
    probes.push_back({{"path", o.path}, {"unit", o.unit}, {"fitted", o.fitted}, {"ci95", RoundedOrNull(o.ci95)},
                      {"low", o.low}, {"high", o.high}, {"probed", o.probed}, {"equivalent", o.equivalent},
                      {"chosen", o.chosen}, {"fit_loss", o.fit_loss}, {"holdout_loss_fitted", o.holdout_loss_fitted},
                      {"holdout_loss", o.holdout_loss}, {"pin_down", TellApartJson(o.pin_down)}});
  }
  return probes;
}

nlohmann::json ScoreJson(const ModelScore& s) {
  nlohmann::json values = nlohmann::json::array();
  for (const FittedValue& v : s.values) {
    values.push_back({{"path", v.path}, {"unit", v.unit}, {"start", v.start}, {"value", v.value},
                      {"ci95", RoundedOrNull(v.ci95)}, {"identified", v.identified}, {"bound", BoundName(v.bound)}});
  }
  return {{"model", s.label},
          {"summary", s.summary},
          {"quantity", s.quantity},
          {"added_parameters", s.added_parameters},
          {"parameters", values},
          {"open_parameters", OpenJson(s.open)},
          {"fit_rms", RoundedOrNull(s.fit_rms)},
          {"holdout_rms", RoundedOrNull(s.holdout_rms)},
          {"score", RoundedOrNull(s.score)},
          {"fit", {{"generations", s.fit.generations}, {"evaluations", s.fit.evaluations},
                   {"converged", s.fit.converged}, {"abandoned", s.fit.abandoned}, {"convergence", s.fit.convergence},
                   {"local_starts", s.fit.local_starts}, {"polish", s.fit.polish}, {"race", s.race}}}};
}

// The motors of the worst channels, worst first, without repeats (for the plots).
std::vector<std::string> WorstChannels(const GapSnapshot& snapshot, std::size_t count) {
  std::vector<std::string> worst;
  for (const ChannelStatistics& c : snapshot.channels) {
    const std::string motor = c.name.substr(c.name.find(':') + 1);
    if (std::find(worst.begin(), worst.end(), motor) == worst.end()) worst.push_back(motor);
    if (worst.size() == count) break;
  }
  return worst;
}

// `digits` significant digits, for fitted values and their uncertainties.
std::string Digits(double value, int digits) { return text::FormatSignificant(value, digits); }

// For an open parameter the held-out runs moved: where the fit had it and what was probed.
std::string ChosenNote(const ModelScore& s, const FittedValue& v) {
  for (const OpenParameter& o : s.open) {
    if (o.path != v.path || o.chosen == o.fitted) continue;
    return " (chosen by the held-out runs among " + std::to_string(o.equivalent) + " values from " + Digits(o.low, 4) +
           " to " + Digits(o.high, 4) + " that fit as well; fitted " + Digits(o.fitted, 4) + ")";
  }
  return "";
}

std::string Number(double value) { return std::isfinite(value) ? text::FormatDouble(value) : ""; }
std::string Deg(double value) {
  return std::isfinite(value) ? text::FormatDouble(std::round(value * 1000.0) / 1000.0) + "°" : "—";
}

void WriteFile(const fs::path& path, const std::string& content) {
  AtomicFile file(path.string());
  file.stream() << content;
  file.Commit();
}

std::string TraceCsv(const ChannelTrace& before, const ChannelTrace& refit, const ChannelTrace* after,
                     double step) {
  const SampleQuantities q = DeriveQuantities(before.measured, step);
  std::ostringstream csv;
  csv << "time,measured,before,refit,after,desired,velocity,speed,acceleration,load,command_error\n";
  for (std::size_t k = 0; k < before.measured.size(); ++k) {
    const double load = k < refit.motor_torque.size() ? refit.motor_torque[k] : std::nan("");
    csv << Number(static_cast<double>(k) * step) << ',' << Number(before.measured[k]) << ','
        << Number(before.simulated[k]) << ',' << Number(refit.simulated[k]) << ','
        << (after != nullptr ? Number(after->simulated[k]) : "") << ',' << Number(before.desired[k]) << ','
        << Number(q.velocity[k]) << ',' << Number(std::abs(q.velocity[k])) << ',' << Number(q.acceleration[k])
        << ',' << Number(load) << ',' << Number(before.desired[k] - before.measured[k]) << '\n';
  }
  return csv.str();
}

nlohmann::json RivalsJson(const Diagnosis& d) {
  nlohmann::json rivals = nlohmann::json::array();
  for (const Rival& r : d.rivals) {
    rivals.push_back({{"effect", r.effect}, {"holdout_ratio", r.ratio}, {"relation", r.relation},
                      {"kind", r.contains_named ? "contains the named effect, fits no better" : "tie"}});
  }
  return rivals;
}

}  // namespace

nlohmann::json ReportJson(const Diagnosis& d, const Rig& rig, const DiagnosisOptions& options) {
  nlohmann::json candidates = nlohmann::json::array();
  for (const ModelScore& c : d.candidates) candidates.push_back(ScoreJson(c));
  nlohmann::json model = nlohmann::json::object();
  for (const Override& value : d.model_values) model[value.first] = value.second;
  const double reduction = d.before.holdout_rms > 0 ? 1.0 - d.after.holdout_rms / d.before.holdout_rms : 0.0;
  return {
      {"rig", rig.kind},
      {"environment", rig.environment_name},
      {"agent", rig.agent},
      {"runs", {{"fit", d.fit_runs}, {"holdout", d.holdout_runs}, {"holdout_in_sample", d.holdout_in_sample}}},
      {"gap", {{"before", SnapshotJson(d.before)}, {"refit", SnapshotJson(d.refit)}, {"after", SnapshotJson(d.after)}}},
      {"refit", ScoreJson(d.base)},
      {"candidates", candidates},
      {"verdict",
       {{"effect", d.effect.empty() ? nlohmann::json(nullptr) : nlohmann::json(d.effect)},
        {"effects", d.effects},
        {"tie", d.effects.size() > 1},
        {"rivals", RivalsJson(d)},
        {"tell_apart", TellApartJson(d.tell_apart)},
        {"text", d.verdict},
        {"quantity", d.quantity},
        {"holdout_rms_before", RoundedOrNull(d.before.holdout_rms)},
        {"holdout_rms_refit", RoundedOrNull(d.refit.holdout_rms)},
        {"holdout_rms_after", RoundedOrNull(d.after.holdout_rms)},
        {"holdout_reduction", RoundedOrNull(reduction)}}},
      {"model", model},
      {"worst_channels", WorstChannels(d.before, 4)},
      {"criterion",
       {{"score", options.loss == Loss::kAbsolute
                      ? "holdout mean absolute error (deg) × (1 + penalty_per_parameter × added parameters)"
                      : "holdout_rms² × (1 + penalty_per_parameter × added parameters)"},
        {"loss", options.loss == Loss::kAbsolute ? "absolute" : "squared"},
        {"penalty_per_parameter", options.penalty_per_parameter},
        {"win_ratio", options.win_ratio},
        {"generations", options.fit.generations},
        {"abandon_share", std::isfinite(options.abandon_share) ? nlohmann::json(options.abandon_share) : nullptr},
        {"early_stop", options.fit.stop_replays_early},
        {"relax_scan", options.relax_scan},
        {"islands", options.fit.islands},
        {"seed", options.fit.seed}}},
      {"cost", {{"seconds", d.seconds}, {"jobs", d.jobs}, {"jobs_stopped_early", d.jobs_stopped_early}}},
  };
}

std::string ModelValueFile(const Diagnosis& d, const std::vector<ValueAssignment>& model) {
  std::ostringstream file;
  file << "# orcs-gap fitted model\n";
  file << "# " << (d.effect.empty() ? "no missing effect found; base parameters refitted" : "added effect: " + d.effect)
       << "\n";
  for (std::size_t i = 1; i < d.effects.size(); ++i) {
    file << "# tied with " << d.effects[i] << ": the held-out runs cannot tell them apart (report.md)\n";
  }
  for (const ValueAssignment& line : model) file << line.path << "=" << line.value << "\n";
  for (const Override& value : d.model_values) file << value.first << "=" << value.second << "\n";
  return file.str();
}

namespace {

// The race of --race, as said in report.md ("" without it).
std::string EarlyStops(const DiagnosisOptions& options) {
  std::ostringstream text;
  if (std::isfinite(options.abandon_share)) {
    text << "; a candidate whose best point after " << options.fit.abandon_after << " generations has a fit error above "
         << kRaceFitShare * 100.0 << " % of the refit's and a held-out score above " << options.abandon_share * 100.0
         << " % of the refit's is abandoned";
  }
  return text.str();
}

// The CMA-ES islands of --islands, as said in report.md ("" without them).
std::string Islands(const DiagnosisOptions& options) {
  if (options.fit.islands <= 0) return "";
  const int islands = options.fit.islands;
  return "; " + std::to_string(islands) + (islands == 1 ? " CMA-ES island" : " CMA-ES islands") +
         " (pagmo2 cmaes, " + std::to_string(options.fit.island_generations) +
         " generations each) from the swarm's last generation, whose best point starts a second compass search and "
         "polish (the better fit is kept)";
}

}  // namespace

std::string ReportMarkdown(const Diagnosis& d, const Rig& rig, const DiagnosisOptions& options) {
  std::ostringstream md;
  md << "# orcs-gap report\n\n";
  md << "Rig: " << rig.kind << " (" << rig.environment_name << "), agent " << rig.agent << ". Fit runs: "
     << d.fit_runs.size() << ", held-out runs: " << d.holdout_runs.size()
     << (d.holdout_in_sample ? " (none given: scores are in-sample)" : "") << ".\n\n";
  md << "## Verdict\n\n" << d.verdict << "\n\n";
  md << "## The gap\n\n| model | fit runs, RMS | held-out runs, RMS |\n|---|---|---|\n";
  md << "| as given | " << Deg(d.before.fit_rms) << " | " << Deg(d.before.holdout_rms) << " |\n";
  md << "| base parameters refitted | " << Deg(d.refit.fit_rms) << " | " << Deg(d.refit.holdout_rms) << " |\n";
  if (!d.effect.empty()) {
    md << "| with " << d.effect << " | " << Deg(d.after.fit_rms) << " | " << Deg(d.after.holdout_rms) << " |\n";
  }
  md << "\n## Per run: mean absolute error / RMS\n\n"
     << "The mean absolute position error (mrad) is the BAM project's metric; RMS in degrees is orcs's.\n\n"
     << "| run | role | as given | refitted |" << (d.effect.empty() ? "" : " with " + d.effect + " |") << "\n"
     << "|---|---|---|---|" << (d.effect.empty() ? "" : "---|") << "\n";
  for (std::size_t r = 0; r < d.before.runs.size(); ++r) {
    md << "| " << d.before.runs[r].run << " | " << (d.before.runs[r].held_out ? "held out" : "fitted") << " | "
       << RunCell(d.before.runs[r]) << " | " << (r < d.refit.runs.size() ? RunCell(d.refit.runs[r]) : "—") << " |";
    if (!d.effect.empty()) md << " " << (r < d.after.runs.size() ? RunCell(d.after.runs[r]) : "—") << " |";
    md << "\n";
  }
  md << "\n## Where the gap is (model as given, worst channels)\n\n"
     << "| channel | RMS | bias | at rest | high speed | reversals | high load | accelerating | best shift |\n"
     << "|---|---|---|---|---|---|---|---|---|\n";
  for (std::size_t i = 0; i < d.before.channels.size() && i < 8; ++i) {
    const ChannelStatistics& c = d.before.channels[i];
    md << "| " << c.name << " | " << Deg(c.rms) << " | " << Deg(c.bias);
    for (const char* regime : {"at_rest", "high_speed", "reversal", "high_load", "accelerating"}) {
      std::string cell = "—";
      for (const RegimeError& r : c.regimes) {
        if (r.regime == regime && r.samples > 0) cell = Deg(r.rms);
      }
      md << " | " << cell;
    }
    md << " | " << text::FormatDouble(std::round(c.best_shift * 1000.0)) << " ms |\n";
  }
  md << "\n## Candidates (best first)\n\n"
     << "| model | added parameters | fit RMS | held-out RMS | score / refit | converged | fitted values |\n"
     << "|---|---|---|---|---|---|---|\n";
  const auto row = [&](const ModelScore& s) {
    md << "| " << s.label << " | " << s.added_parameters << " | " << Deg(s.fit_rms) << " | " << Deg(s.holdout_rms)
       << " | " << text::FormatDouble(std::round(s.score / d.base.score * 1000.0) / 1000.0) << " | "
       << (s.fit.abandoned ? "abandoned after " + std::to_string(s.fit.generations) + " generations, converged " +
                                 (s.fit.converged ? "yes" : "no")
                           : s.fit.converged ? "yes" : "no")
       << " |";
    for (const FittedValue& v : s.values) {
      md << " " << v.path.substr(v.path.rfind('/') + 1) << " " << Digits(v.value, 4)
         << (std::isfinite(v.ci95) ? " ± " + Digits(v.ci95, 3) : "") << " " << v.unit
         << (v.identified || s.fit.abandoned ? "" : " (not identified)") << ChosenNote(s, v) << BoundNote(v.bound)
         << ";";
    }
    md << " |\n";
  };
  row(d.base);
  for (const ModelScore& s : d.candidates) row(s);
  md << "\nScore: held-out " << (options.loss == Loss::kAbsolute ? "mean absolute error" : "RMS²") << " × (1 + "
     << options.penalty_per_parameter
     << " × added parameters); an effect is named when its score is below " << options.win_ratio
     << " × the refit's. Fits (minimising the mean "
     << (options.loss == Loss::kAbsolute ? "absolute" : "squared") << " angle error): each effect's main parameter "
     << "scanned over its range"
     << (options.relax_scan ? " (its best points relaxed)" : "") << ", then a particle swarm (pagmo2 "
     << "pso_gen), " << options.fit.generations << " generations" << EarlyStops(options) << ", seed "
     << options.fit.seed << ", a compass search and a Levenberg–Marquardt polish (Ceres)" << Islands(options)
     << "; ± is the 95 % confidence interval from the "
     << "Jacobian. " << d.jobs << " replay jobs (" << d.jobs_stopped_early
     << " stopped early: their point could not beat the search's best) in "
     << text::FormatDouble(std::round(d.seconds * 10) / 10) << " s.\n\nPlots: `scripts/plot_gap.py DIR` → DIR/plots/.\n";
  return md.str();
}

void WriteReport(const std::string& folder, const Diagnosis& d, const Rig& rig,
                 const std::vector<ValueAssignment>& model, const DiagnosisOptions& options) {
  const fs::path root(folder);
  std::error_code error;
  fs::create_directories(root / "traces", error);
  if (error) throw InputError(folder + ": cannot create the output folder: " + error.message());
  WriteFile(root / "model.val", ModelValueFile(d, model));
  WriteFile(root / "report.json", ReportJson(d, rig, options).dump(2) + "\n");
  WriteFile(root / "report.md", ReportMarkdown(d, rig, options));
  for (std::size_t r = 0; r < d.before.traces.size(); ++r) {
    for (std::size_t c = 0; c < d.before.traces[r].size(); ++c) {
      const ChannelTrace& before = d.before.traces[r][c];
      std::string name = before.name;
      std::replace(name.begin(), name.end(), '/', '_');
      std::replace(name.begin(), name.end(), ':', '.');
      const ChannelTrace* after = d.effect.empty() ? nullptr : &d.after.traces[r][c];
      WriteFile(root / "traces" / (name + ".csv"), TraceCsv(before, d.refit.traces[r][c], after, rig.step));
    }
  }
}

void WriteReplays(const std::string& folder, const Diagnosis& d, const Rig& rig,
                  const std::vector<ValueAssignment>& model, const std::vector<ReplayRun>& runs) {
  const fs::path replays = fs::path(folder) / "replays";
  std::error_code error;
  fs::create_directories(replays, error);
  if (error) throw InputError(replays.string() + ": cannot create the folder: " + error.message());
  for (const fs::directory_entry& entry : fs::directory_iterator(replays, error)) {
    if (entry.is_regular_file() && entry.path().extension() == ".orcsrec") fs::remove(entry.path(), error);
  }
  std::set<std::string> written;
  for (const ReplayRun& run : runs) {
    if (!written.insert(run.name).second) continue;  // a run both fitted and held out (in-sample) once
    const auto write = [&](const std::string& suffix, const std::string& bytes) {
      if (!bytes.empty()) evaluation::WriteRecording((replays / (run.name + suffix)).string(), bytes);
    };
    const auto fitted = d.after.recordings.find(run.name);
    if (fitted != d.after.recordings.end()) write(".orcsrec", fitted->second);
    const auto given = d.before.recordings.find(run.name);
    if (given != d.before.recordings.end()) write(".given.orcsrec", given->second);
    write(".measured.orcsrec", MeasuredRecording(rig, model, run));
  }
}

}  // namespace orcs::gap
