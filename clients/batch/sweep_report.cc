#include "clients/batch/sweep_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <unordered_map>

#include "model/core/atomic_file.h"
#include "model/core/text.h"

namespace orcs::batch {
using runtime::JobSource;
using runtime::PlannedJob;
using runtime::PlannedJobList;
using runtime::SweepPoint;
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// "PID/Proportional" for "/AngularMotor/PID/Proportional": short enough for a column, still telling.
std::string ColumnName(const std::string& path) {
  const std::size_t last = path.rfind('/');
  if (last == std::string::npos || last == 0) return path;
  const std::size_t before = path.rfind('/', last - 1);
  return path.substr(before + 1);
}

std::string Cell(double value, int decimals) {
  if (std::isnan(value)) return "-";
  char text[64];
  std::snprintf(text, sizeof text, "%.*g", decimals, value);
  return text;
}

std::string CsvNumber(double value) { return std::isnan(value) ? "" : text::FormatDouble(value); }

}  // namespace

std::vector<SweepRow> SweepRows(const std::vector<SweepPoint>& points, const std::vector<PlannedJob>& jobs,
                                const std::vector<v1::Result>& results) {
  return SweepRows(points, PlannedJobList(jobs), results);
}

std::vector<SweepRow> SweepRows(const std::vector<SweepPoint>& points, const JobSource& jobs,
                                const std::vector<v1::Result>& results) {
  std::vector<SweepRow> rows(points.size());
  std::vector<double> sums(points.size(), 0.0);
  for (std::size_t p = 0; p < points.size(); ++p) {
    rows[p].point = points[p];
    rows[p].fitness = rows[p].min_fitness = rows[p].max_fitness = kNaN;
  }
  std::unordered_map<std::string, std::size_t> point_of;
  for (std::size_t i = 0; i < jobs.size(); ++i) {
    const PlannedJob planned = jobs.Job(i);
    const std::size_t p = planned.extra.at("point").get<std::size_t>();
    point_of[planned.job.job_id()] = p;
    ++rows[p].jobs;
  }
  for (const v1::Result& result : results) {
    const auto it = point_of.find(result.job_id());
    if (it == point_of.end() || result.status() != v1::Result::OK) continue;
    SweepRow& row = rows[it->second];
    const double f = result.fitness();
    row.min_fitness = row.ok == 0 ? f : std::min(row.min_fitness, f);
    row.max_fitness = row.ok == 0 ? f : std::max(row.max_fitness, f);
    sums[it->second] += f;
    ++row.ok;
  }
  for (std::size_t p = 0; p < rows.size(); ++p) {
    if (rows[p].ok > 0) rows[p].fitness = sums[p] / rows[p].ok;
  }
  return rows;
}

std::string SweepTable(const std::vector<SweepAxis>& axes, const std::vector<SweepRow>& rows) {
  std::vector<std::string> header;
  for (const SweepAxis& axis : axes) header.push_back(ColumnName(axis.path));
  for (const char* name : {"fitness", "min", "max", "ok/jobs"}) header.emplace_back(name);
  std::vector<std::vector<std::string>> cells;
  for (const SweepRow& row : rows) {
    std::vector<std::string> line;
    for (const auto& [path, value] : row.point) {
      line.push_back(value.categorical() ? value.text : Cell(value.number, 6));
    }
    line.push_back(Cell(row.fitness, 6));
    line.push_back(Cell(row.min_fitness, 6));
    line.push_back(Cell(row.max_fitness, 6));
    line.push_back(std::to_string(row.ok) + "/" + std::to_string(row.jobs));
    cells.push_back(std::move(line));
  }
  std::vector<std::size_t> width(header.size());
  for (std::size_t c = 0; c < header.size(); ++c) {
    width[c] = header[c].size();
    for (const auto& line : cells) width[c] = std::max(width[c], line[c].size());
  }
  auto format = [&](const std::vector<std::string>& line) {
    std::string text;
    for (std::size_t c = 0; c < line.size(); ++c) {
      text += (c == 0 ? "" : "  ") + std::string(width[c] - line[c].size(), ' ') + line[c];
    }
    return text + "\n";
  };
  std::string table = format(header);
  for (const auto& line : cells) table += format(line);
  return table;
}

void WriteSweepCsv(const std::string& folder, const std::vector<SweepAxis>& axes, const std::vector<SweepRow>& rows) {
  AtomicFile file((std::filesystem::path(folder) / "sweep.csv").string());
  std::ostream& out = file.stream();
  for (const SweepAxis& axis : axes) out << axis.path << ',';
  out << "fitness,min_fitness,max_fitness,ok,jobs\n";
  for (const SweepRow& row : rows) {
    for (const auto& [path, value] : row.point) out << value.OverrideText() << ',';
    out << CsvNumber(row.fitness) << ',' << CsvNumber(row.min_fitness) << ',' << CsvNumber(row.max_fitness) << ','
        << row.ok << ',' << row.jobs << '\n';
  }
  file.Commit();
}

}  // namespace orcs::batch
