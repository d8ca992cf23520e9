#include "clients/batch/robustness_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <nlohmann/json.hpp>
#include <numeric>

#include "model/core/atomic_file.h"
#include "model/scene/scenario.h"

namespace orcs::batch {
using runtime::SweepPoint;
using runtime::SweepValue;
namespace {

using Json = nlohmann::ordered_json;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string Short(double value) {
  if (std::isnan(value)) return "-";
  char text[32];
  std::snprintf(text, sizeof text, "%.4g", value);
  return text;
}

const char* SamplingName(SweepSampling sampling) { return sampling == SweepSampling::kGrid ? "grid" : "lhs"; }

FitnessDistribution Distribute(std::vector<double> values, int points) {
  FitnessDistribution d;
  d.points = points;
  d.ok_points = static_cast<int>(values.size());
  if (values.empty()) {
    d.mean = d.deviation = d.min = d.q1 = d.median = d.q3 = d.max = kNaN;
    return d;
  }
  const double n = static_cast<double>(values.size());
  d.mean = std::accumulate(values.begin(), values.end(), 0.0) / n;
  double squares = 0.0;
  for (double value : values) squares += (value - d.mean) * (value - d.mean);
  d.deviation = values.size() > 1 ? std::sqrt(squares / (n - 1.0)) : 0.0;
  const auto quantile = [&values](double q) { return scene::AggregateFitness(values, scene::Aggregate::kQuantile, q); };
  d.min = quantile(0.0);
  d.q1 = quantile(0.25);
  d.median = quantile(0.5);
  d.q3 = quantile(0.75);
  d.max = quantile(1.0);
  return d;
}

bool HasFitness(const SweepRow& row) { return row.ok > 0 && std::isfinite(row.fitness); }

std::string PointText(const SweepPoint& point, const char* separator) {
  std::string text;
  for (const auto& [path, value] : point) {
    text += (text.empty() ? "" : ", ") + path + separator + (value.categorical() ? value.text : Short(value.number));
  }
  return text;
}

// "X (S 0.62)", with a warning when S does not clear what an input without effect may get.
std::string RankedName(const ParameterSensitivity& p) {
  const Sensitivity& s = p.sensitivity;
  std::string text = p.path + " (S " + Short(s.index);
  if (!std::isnan(s.index) && s.index <= s.noise_floor) text += ", within the noise: below " + Short(s.noise_floor);
  return text + ")";
}

Json NumberOrNull(double value) { return std::isfinite(value) ? Json(value) : Json(nullptr); }

Json PointJson(const SweepPoint& point) {
  Json params = Json::object();
  for (const auto& [path, value] : point) params[path] = value.categorical() ? Json(value.text) : Json(value.number);
  return params;
}

Json ReportJson(const RobustnessReport& report, const std::vector<SweepRow>& rows) {
  const FitnessDistribution& d = report.fitness;
  Json json;
  json["title"] = report.title;
  json["sampling"] = SamplingName(report.sampling);
  json["points"] = d.points;
  json["ok_points"] = d.ok_points;
  json["fitness"] = {{"mean", NumberOrNull(d.mean)},     {"deviation", NumberOrNull(d.deviation)},
                     {"min", NumberOrNull(d.min)},       {"q1", NumberOrNull(d.q1)},
                     {"median", NumberOrNull(d.median)}, {"q3", NumberOrNull(d.q3)},
                     {"max", NumberOrNull(d.max)}};
  if (report.worst) {
    const SweepRow& row = rows[*report.worst];
    json["worst"] = {{"point", *report.worst}, {"params", PointJson(row.point)},
                     {"fitness", row.fitness}, {"min_fitness", row.min_fitness},
                     {"ok", row.ok},           {"jobs", row.jobs}};
  } else {
    json["worst"] = nullptr;
  }
  Json sensitivity = Json::array();
  for (const ParameterSensitivity& p : report.parameters) {
    Json bins = Json::array();
    for (const SensitivityBin& bin : p.sensitivity.bins) {
      bins.push_back(
          {{"label", bin.label}, {"low", bin.low}, {"high", bin.high}, {"count", bin.count}, {"mean", bin.mean}});
    }
    sensitivity.push_back({{"path", p.path},
                           {"kind", p.categorical ? "categorical" : "numeric"},
                           {"index", NumberOrNull(p.sensitivity.index)},
                           {"noise_floor", p.sensitivity.noise_floor},
                           {"bins", std::move(bins)}});
  }
  json["sensitivity"] = std::move(sensitivity);
  Json ranking = Json::array();
  for (std::size_t i : report.ranking) ranking.push_back(report.parameters[i].path);
  json["ranking"] = std::move(ranking);
  return json;
}

std::string ReportMarkdown(const RobustnessReport& report, const std::vector<SweepRow>& rows) {
  const FitnessDistribution& d = report.fitness;
  std::string md = "# Robustness: " + report.title + "\n\n";
  md += std::to_string(d.points) + " points (" +
        (report.sampling == SweepSampling::kGrid ? "grid" : "Latin hypercube sample") + "), " +
        std::to_string(d.ok_points) + " with an ok run. A point's fitness is the mean over its ok repeats.\n\n";
  md += "| | mean | sd | min | q1 | median | q3 | max |\n|---|---|---|---|---|---|---|---|\n";
  md += "| fitness | " + Short(d.mean) + " | " + Short(d.deviation) + " | " + Short(d.min) + " | " + Short(d.q1) +
        " | " + Short(d.median) + " | " + Short(d.q3) + " | " + Short(d.max) + " |\n\n";
  if (report.worst) {
    md += "**Worst point** " + std::to_string(*report.worst) + " (fitness " + Short(rows[*report.worst].fitness) +
          "): " + PointText(rows[*report.worst].point, " = ") + "\n\n";
  }
  md +=
      "## Sensitivity\n\nFirst-order index S = Var(E[fitness | X]) / Var(fitness), E[fitness | X] estimated by the "
      "mean fitness over bins of X (equal-count bins of a number, one bin per category). A parameter without any "
      "effect gets S ≈ (bins − 1)/(points − 1) and stays below the noise floor about 97 % of the time: an S below it "
      "cannot be told from no effect.\n\n";
  md += "| rank | parameter | S | noise floor | bins |\n|---|---|---|---|---|\n";
  for (std::size_t r = 0; r < report.ranking.size(); ++r) {
    const ParameterSensitivity& p = report.parameters[report.ranking[r]];
    md += "| " + std::to_string(r + 1) + " | `" + p.path + "` | " + Short(p.sensitivity.index) + " | " +
          Short(p.sensitivity.noise_floor) + " | " + std::to_string(p.sensitivity.bins.size()) + " |\n";
  }
  md += "\nFitness " + RankingText(report) + ".\n";
  for (const ParameterSensitivity& p : report.parameters) {
    md += "\n### `" + p.path + "`\n\n| " + std::string(p.categorical ? "value" : "bin") +
          " | points | mean fitness |\n|---|---|---|\n";
    for (const SensitivityBin& bin : p.sensitivity.bins) {
      md += "| " + bin.label + " | " + std::to_string(bin.count) + " | " + Short(bin.mean) + " |\n";
    }
  }
  return md;
}

}  // namespace

RobustnessReport MakeRobustnessReport(const std::string& title, SweepSampling sampling,
                                      const std::vector<SweepAxis>& axes, const std::vector<SweepRow>& rows) {
  RobustnessReport report;
  report.title = title;
  report.sampling = sampling;
  std::vector<double> y;
  std::vector<std::vector<SweepValue>> x(axes.size());
  for (std::size_t p = 0; p < rows.size(); ++p) {
    if (!HasFitness(rows[p])) continue;
    y.push_back(rows[p].fitness);
    for (std::size_t a = 0; a < axes.size(); ++a) x[a].push_back(rows[p].point.at(a).second);
    if (!report.worst || rows[p].fitness < rows[*report.worst].fitness) report.worst = p;
  }
  report.fitness = Distribute(y, static_cast<int>(rows.size()));
  const int bins = DefaultBinCount(y.size());
  for (std::size_t a = 0; a < axes.size(); ++a) {
    report.parameters.push_back({axes[a].path, axes[a].categorical(), FirstOrderSensitivity(x[a], y, bins)});
  }
  report.ranking.resize(axes.size());
  std::iota(report.ranking.begin(), report.ranking.end(), std::size_t{0});
  const auto key = [&report](std::size_t i) {
    const double s = report.parameters[i].sensitivity.index;
    return std::isnan(s) ? -1.0 : s;
  };
  std::stable_sort(report.ranking.begin(), report.ranking.end(),
                   [&key](std::size_t a, std::size_t b) { return key(a) > key(b); });
  return report;
}

std::string RankingText(const RobustnessReport& report) {
  if (report.ranking.empty()) return "depends on no swept parameter";
  if (std::isnan(report.parameters[report.ranking.front()].sensitivity.index)) {
    return "did not vary over the points: no parameter explains anything";
  }
  std::string text = "most sensitive to " + RankedName(report.parameters[report.ranking.front()]);
  for (std::size_t r = 1; r < report.ranking.size(); ++r) {
    text += (r == 1 ? ", then " : ", ") + RankedName(report.parameters[report.ranking[r]]);
  }
  return text;
}

std::string RobustnessSummary(const RobustnessReport& report, const std::vector<SweepRow>& rows) {
  const FitnessDistribution& d = report.fitness;
  std::string text = "orcs-batch: fitness over " + std::to_string(d.ok_points) + " of " + std::to_string(d.points) +
                     " points: mean " + Short(d.mean) + " (sd " + Short(d.deviation) + "), min " + Short(d.min) +
                     ", quartiles " + Short(d.q1) + " / " + Short(d.median) + " / " + Short(d.q3) + ", max " +
                     Short(d.max) + "\n";
  if (report.worst) {
    text += "orcs-batch: worst point " + std::to_string(*report.worst) + " (" +
            PointText(rows[*report.worst].point, "=") + "): fitness " + Short(rows[*report.worst].fitness) + "\n";
  }
  return text + "orcs-batch: fitness " + RankingText(report) + "\n";
}

void WriteRobustnessReport(const std::string& folder, const RobustnessReport& report,
                           const std::vector<SweepRow>& rows) {
  AtomicFile json((std::filesystem::path(folder) / "robustness.json").string());
  json.stream() << ReportJson(report, rows).dump(1) << "\n";
  json.Commit();
  AtomicFile md((std::filesystem::path(folder) / "robustness.md").string());
  md.stream() << ReportMarkdown(report, rows);
  md.Commit();
}

}  // namespace orcs::batch
