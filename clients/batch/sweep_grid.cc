#include "clients/batch/sweep_grid.h"

#include <cmath>
#include <optional>
#include <set>

#include "model/core/error.h"
#include "model/core/text.h"
#include "model/physics/material_table.h"

namespace orcs::batch {
using runtime::SweepPoint;
using runtime::SweepValue;
namespace {

constexpr int kMaxSteps = 10000;

[[noreturn]] void Fail(const std::string& text, const std::string& what) {
  throw InputError("--param " + text::Quote(text), 0, what);
}

double FiniteNumber(const std::string& text, const std::string& field, const std::string& name) {
  const std::optional<double> value = text::ParseDouble(field);
  if (!value || !std::isfinite(*value)) Fail(text, name + " expected a finite number, found " + text::Quote(field));
  return *value;
}

std::string MaterialNames() {
  std::string names;
  for (int i = 0; i < physics::MaterialTable::kCount; ++i) {
    names += (i == 0 ? "" : ", ") + std::string(physics::MaterialTable::NameOf(i));
  }
  return names;
}

// A material the table does not know is legal in a world (the fallback friction applies), but in a sweep it is
// almost always a typo that would silently sweep a frictionless floor: refuse it.
void CheckMaterial(const std::string& text, const std::string& path, const std::string& value) {
  if (!path.ends_with("/Material")) return;
  if (physics::MaterialTable::IndexOf(value) == physics::MaterialTable::kUnknown) {
    Fail(text, text::Quote(value) + " is not a material; expected one of " + MaterialNames());
  }
}

// "V1,V2,...": one category per value, in the order given.
void ParseCategories(const std::string& text, const std::string& list, SweepAxis& axis) {
  std::set<std::string> seen;
  for (std::string_view field : text::Split(list, ',')) {
    const std::string value(field);
    if (value.empty()) Fail(text, "expected a list of values V1,V2,... without empty ones");
    if (value.find_first_of("\"\r\n") != std::string::npos) Fail(text, "a value may not hold '\"' or a line break");
    if (!seen.insert(value).second) Fail(text, "the value " + text::Quote(value) + " is listed twice");
    CheckMaterial(text, axis.path, value);
    axis.categories.push_back(value);
  }
  if (axis.categories.size() > static_cast<std::size_t>(kMaxSteps)) {
    Fail(text, "expected at most " + std::to_string(kMaxSteps) + " values");
  }
  axis.steps = static_cast<int>(axis.categories.size());
  axis.low = 0.0;
  axis.high = static_cast<double>(axis.steps - 1);
}

void ParseGridRange(const std::string& text, const std::vector<std::string>& fields, SweepAxis& axis) {
  if (fields.size() != 3) {
    Fail(text, "expected LOW:HIGH:STEPS after '=', found " + std::to_string(fields.size()) + " fields");
  }
  axis.low = FiniteNumber(text, fields[0], "LOW");
  axis.high = FiniteNumber(text, fields[1], "HIGH");
  const std::optional<long long> steps = text::ParseInt(fields[2]);
  if (!steps || *steps < 1 || *steps > kMaxSteps) {
    Fail(text, "STEPS expected an integer from 1 to " + std::to_string(kMaxSteps) + ", found " + text::Quote(fields[2]));
  }
  axis.steps = static_cast<int>(*steps);
  if (axis.low > axis.high) Fail(text, "LOW " + fields[0] + " is above HIGH " + fields[1]);
  if (axis.steps == 1 && axis.low != axis.high) Fail(text, "STEPS 1 needs LOW equal to HIGH");
}

void ParseInterval(const std::string& text, const std::vector<std::string>& fields, SweepAxis& axis) {
  if (fields.size() != 2) {
    Fail(text, "expected LOW:HIGH after '=' for --sample lhs (no STEPS: every sample is its own value), found " +
                   std::to_string(fields.size()) + " fields");
  }
  axis.low = FiniteNumber(text, fields[0], "LOW");
  axis.high = FiniteNumber(text, fields[1], "HIGH");
  if (axis.low > axis.high) Fail(text, "LOW " + fields[0] + " is above HIGH " + fields[1]);
  axis.steps = 0;
}

}  // namespace

double SweepAxis::ValueAt(int i) const {
  if (steps <= 1 || i == 0) return low;
  if (i == steps - 1) return high;
  return low + (high - low) * static_cast<double>(i) / static_cast<double>(steps - 1);
}

SweepValue SweepAxis::GridValue(int i) const {
  if (categorical()) return SweepValue(categories.at(static_cast<std::size_t>(i)), i);
  return ValueAt(i);
}

SweepAxis ParseSweepAxis(const std::string& text, SweepSampling sampling) {
  const bool grid = sampling == SweepSampling::kGrid;
  const std::size_t equals = text.find('=');
  if (equals == std::string::npos) {
    Fail(text, grid ? "expected PATH=LOW:HIGH:STEPS or PATH=V1,V2,..." : "expected PATH=LOW:HIGH or PATH=V1,V2,...");
  }
  SweepAxis axis;
  axis.path = text.substr(0, equals);
  if (!axis.path.starts_with('/')) Fail(text, "expected a repository path starting with '/', found " + text::Quote(axis.path));
  const std::string range = text.substr(equals + 1);
  if (range.find(':') == std::string::npos) {
    ParseCategories(text, range, axis);
    return axis;
  }
  std::vector<std::string> fields;
  for (std::string_view field : text::Split(range, ':')) fields.emplace_back(field);
  if (grid) {
    ParseGridRange(text, fields, axis);
  } else {
    ParseInterval(text, fields, axis);
  }
  return axis;
}

void CheckDistinctPaths(const std::vector<SweepAxis>& axes) {
  std::set<std::string> paths;
  for (const SweepAxis& axis : axes) {
    if (!paths.insert(axis.path).second) throw InputError("--param", 0, "the path " + axis.path + " is swept twice");
  }
}

std::vector<SweepPoint> SweepGrid(const std::vector<SweepAxis>& axes, std::size_t max_points) {
  CheckDistinctPaths(axes);
  std::size_t count = 1;
  for (const SweepAxis& axis : axes) {
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
      point[a] = {axes[a].path, axes[a].GridValue(i)};
    }
    points.push_back(std::move(point));
  }
  return points;
}

}  // namespace orcs::batch
