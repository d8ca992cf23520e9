#include "clients/batch/sweep_grid.h"

#include <cmath>
#include <optional>
#include <set>

#include "model/core/error.h"
#include "model/core/text.h"

namespace orcs::batch {
namespace {

constexpr int kMaxSteps = 10000;

[[noreturn]] void Fail(const std::string& text, const std::string& what) {
  throw InputError("--param '" + text + "'", 0, what);
}

double FiniteNumber(const std::string& text, const std::string& field, const std::string& name) {
  const std::optional<double> value = text::ParseDouble(field);
  if (!value || !std::isfinite(*value)) Fail(text, name + " expected a finite number, found '" + field + "'");
  return *value;
}

}  // namespace

double SweepAxis::ValueAt(int i) const {
  if (steps <= 1 || i == 0) return low;
  if (i == steps - 1) return high;
  return low + (high - low) * static_cast<double>(i) / static_cast<double>(steps - 1);
}

SweepAxis ParseSweepAxis(const std::string& text) {
  const std::size_t equals = text.find('=');
  if (equals == std::string::npos) Fail(text, "expected PATH=LOW:HIGH:STEPS");
  SweepAxis axis;
  axis.path = text.substr(0, equals);
  if (!axis.path.starts_with('/')) Fail(text, "expected a repository path starting with '/', found '" + axis.path + "'");
  const std::string range = text.substr(equals + 1);
  std::vector<std::string> fields;
  for (std::string_view field : text::Split(range, ':')) fields.emplace_back(field);
  if (fields.size() != 3) Fail(text, "expected LOW:HIGH:STEPS after '=', found " + std::to_string(fields.size()) + " fields");
  axis.low = FiniteNumber(text, fields[0], "LOW");
  axis.high = FiniteNumber(text, fields[1], "HIGH");
  const std::optional<long long> steps = text::ParseInt(fields[2]);
  if (!steps || *steps < 1 || *steps > kMaxSteps) {
    Fail(text, "STEPS expected an integer from 1 to " + std::to_string(kMaxSteps) + ", found '" + fields[2] + "'");
  }
  axis.steps = static_cast<int>(*steps);
  if (axis.low > axis.high) Fail(text, "LOW " + fields[0] + " is above HIGH " + fields[1]);
  if (axis.steps == 1 && axis.low != axis.high) Fail(text, "STEPS 1 needs LOW equal to HIGH");
  return axis;
}

std::vector<SweepPoint> SweepGrid(const std::vector<SweepAxis>& axes, std::size_t max_points) {
  std::set<std::string> paths;
  std::size_t count = 1;
  for (const SweepAxis& axis : axes) {
    if (!paths.insert(axis.path).second) throw InputError("--param", 0, "the path " + axis.path + " is swept twice");
    count *= static_cast<std::size_t>(axis.steps);
    if (count > max_points) {
      throw InputError("--param", 0, "the grid has more than " + std::to_string(max_points) + " points");
    }
  }
  std::vector<SweepPoint> points;
  points.reserve(count);
  for (std::size_t n = 0; n < count; ++n) {
    SweepPoint point(axes.size());
    std::size_t rest = n;
    for (std::size_t a = axes.size(); a-- > 0;) {  // last axis varies fastest
      const int i = static_cast<int>(rest % static_cast<std::size_t>(axes[a].steps));
      rest /= static_cast<std::size_t>(axes[a].steps);
      point[a] = {axes[a].path, axes[a].ValueAt(i)};
    }
    points.push_back(std::move(point));
  }
  return points;
}

}  // namespace orcs::batch
