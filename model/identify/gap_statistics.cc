#include "model/identify/gap_statistics.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <stdexcept>

namespace orcs::identify {
namespace {

constexpr std::size_t kSlopeHalfWindow = 5;    // samples each side of the least-squares slope
constexpr double kRestSpeed = 5.0;             // deg/s: slower is at rest
constexpr double kHighSpeedFloor = 20.0;       // deg/s: high speed is at least this fast
constexpr double kMovingSpeed = 10.0;          // deg/s: a stretch faster than this has a direction
constexpr double kReversalHalfWidth = 0.1;     // s each side of a reversal
constexpr double kHighLoadFloor = 0.05;        // N·m: high load is more than this
constexpr double kAcceleratingFloor = 200.0;   // deg/s²: accelerating is more than this
constexpr double kUpperQuartile = 0.75;        // the percentile above which speed, load, acceleration are high
constexpr int kMaxShift = 25;                  // samples each way the time shift is searched
constexpr double kTimeTolerance = 1e-9;        // s: sample times this close to a bound count as on it

void CheckStep(double step) {
  if (!(std::isfinite(step) && step > 0.0)) {
    throw std::invalid_argument("gap statistics: step must be a positive number of seconds, not " +
                                std::to_string(step));
  }
}

void CheckLength(const ChannelTrace& trace, const char* what, std::size_t size) {
  if (size != trace.measured.size()) {
    throw std::invalid_argument("gap statistics: channel " + trace.name + " has " +
                                std::to_string(trace.measured.size()) + " measured samples but " +
                                std::to_string(size) + " " + what);
  }
}

// Percentiles sort the values, which needs them all to be numbers.
void CheckFinite(const ChannelTrace& trace, const char* what, const std::vector<double>& values) {
  for (std::size_t k = 0; k < values.size(); ++k) {
    if (!std::isfinite(values[k])) {
      throw std::invalid_argument("gap statistics: channel " + trace.name + ": " + what + " sample " +
                                  std::to_string(k) + " is not a finite number");
    }
  }
}

void CheckTrace(const ChannelTrace& trace) {
  CheckLength(trace, "simulated", trace.simulated.size());
  if (!trace.desired.empty()) CheckLength(trace, "desired", trace.desired.size());
  if (!trace.motor_torque.empty()) CheckLength(trace, "motor_torque", trace.motor_torque.size());
  CheckFinite(trace, "measured", trace.measured);
  CheckFinite(trace, "simulated", trace.simulated);
  CheckFinite(trace, "motor_torque", trace.motor_torque);
}

// The least-squares slope per second of `values` (sampled every `step`) over ±kSlopeHalfWindow samples
// around each sample, the window cut at the ends.
std::vector<double> LocalSlope(const std::vector<double>& values, double step) {
  const std::size_t n = values.size();
  std::vector<double> slope(n, 0.0);
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t first = k >= kSlopeHalfWindow ? k - kSlopeHalfWindow : 0;
    const std::size_t last = std::min(n - 1, k + kSlopeHalfWindow);
    const double count = static_cast<double>(last - first + 1);
    double mean_index = 0.0;
    double mean_value = 0.0;
    for (std::size_t i = first; i <= last; ++i) {
      mean_index += static_cast<double>(i);
      mean_value += values[i];
    }
    mean_index /= count;
    mean_value /= count;
    double covariance = 0.0;
    double variance = 0.0;
    for (std::size_t i = first; i <= last; ++i) {
      const double di = static_cast<double>(i) - mean_index;
      covariance += di * (values[i] - mean_value);
      variance += di * di;
    }
    if (variance > 0.0) slope[k] = covariance / variance / step;
  }
  return slope;
}

std::vector<double> Residual(const ChannelTrace& trace) {
  std::vector<double> residual(trace.measured.size());
  for (std::size_t k = 0; k < residual.size(); ++k) residual[k] = trace.measured[k] - trace.simulated[k];
  return residual;
}

std::vector<double> Absolute(const std::vector<double>& values) {
  std::vector<double> result(values.size());
  std::transform(values.begin(), values.end(), result.begin(), [](double x) { return std::abs(x); });
  return result;
}

// The `fraction` percentile of `values`, interpolated linearly between the sorted values; 0 when empty.
double Percentile(std::vector<double> values, double fraction) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const double position = fraction * static_cast<double>(values.size() - 1);
  const std::size_t below = static_cast<std::size_t>(std::floor(position));
  const std::size_t above = std::min(below + 1, values.size() - 1);
  return values[below] + (position - static_cast<double>(below)) * (values[above] - values[below]);
}

// The samples whose value is at least the upper quartile of all values and above `floor`.
std::vector<bool> UpperQuartileAbove(const std::vector<double>& magnitudes, double floor) {
  const double quartile = Percentile(magnitudes, kUpperQuartile);
  std::vector<bool> in(magnitudes.size());
  for (std::size_t k = 0; k < in.size(); ++k) in[k] = magnitudes[k] >= quartile && magnitudes[k] > floor;
  return in;
}

std::vector<bool> AtRest(const std::vector<double>& speed) {
  std::vector<bool> in(speed.size());
  for (std::size_t k = 0; k < in.size(); ++k) in[k] = speed[k] < kRestSpeed;
  return in;
}

std::vector<bool> HighSpeed(const std::vector<double>& speed) {
  const double threshold = std::max(kHighSpeedFloor, Percentile(speed, kUpperQuartile));
  std::vector<bool> in(speed.size());
  for (std::size_t k = 0; k < in.size(); ++k) in[k] = speed[k] >= threshold;
  return in;
}

int Sign(double x) { return x > 0.0 ? 1 : (x < 0.0 ? -1 : 0); }

// The time (s) at which `v` last crosses `level` upwards in `direction` in (from, to]: v[from] is below the
// level (in `direction`), v[to] above it.
double LastCrossingTime(const std::vector<double>& v, std::size_t from, std::size_t to, int direction, double level,
                        double step) {
  const auto above = [&](std::size_t k) { return direction * v[k] > level; };
  std::size_t m = to;
  while (m > from + 1 && above(m - 1)) --m;
  const double before = direction * v[m - 1] - level;  // ≤ 0
  const double after = direction * v[m] - level;       // > 0
  return (static_cast<double>(m - 1) + before / (before - after)) * step;
}

// The times (s) at which the motion reverses: between a stretch with |v| > kMovingSpeed one way and the next
// such stretch the other way, v's last sign change, but no earlier than kReversalHalfWidth before v last rose
// through kRestSpeed in the new direction (in a pause v's sign is noise and may have changed long before).
std::vector<double> ReversalTimes(const std::vector<double>& v, double step) {
  std::vector<double> times;
  int last_direction = 0;
  std::size_t last_moving = 0;
  for (std::size_t k = 0; k < v.size(); ++k) {
    if (std::abs(v[k]) <= kMovingSpeed) continue;
    const int direction = Sign(v[k]);
    if (last_direction != 0 && direction != last_direction) {
      const double sign_change = LastCrossingTime(v, last_moving, k, direction, 0.0, step);
      const double departure = LastCrossingTime(v, last_moving, k, direction, kRestSpeed, step);
      times.push_back(std::max(sign_change, departure - kReversalHalfWidth));
    }
    last_direction = direction;
    last_moving = k;
  }
  return times;
}

std::vector<bool> NearReversals(const std::vector<double>& v, double step) {
  std::vector<bool> in(v.size(), false);
  if (v.empty()) return in;
  const double last = static_cast<double>(v.size() - 1);
  for (const double time : ReversalTimes(v, step)) {
    const double first_index = std::max(0.0, std::ceil((time - kReversalHalfWidth - kTimeTolerance) / step));
    const double last_index = std::min(last, std::floor((time + kReversalHalfWidth + kTimeTolerance) / step));
    for (double k = first_index; k <= last_index; k += 1.0) in[static_cast<std::size_t>(k)] = true;
  }
  return in;
}

RegimeError Regime(std::string_view name, const std::vector<double>& residual, const std::vector<bool>& in) {
  RegimeError regime;
  regime.regime = std::string(name);
  double sum_of_squares = 0.0;
  for (std::size_t k = 0; k < residual.size(); ++k) {
    if (!in[k]) continue;
    sum_of_squares += residual[k] * residual[k];
    ++regime.samples;
  }
  if (regime.samples > 0) {
    regime.rms = std::sqrt(sum_of_squares / regime.samples);
    regime.share = static_cast<double>(regime.samples) / static_cast<double>(residual.size());
  }
  return regime;
}

std::vector<RegimeError> Regimes(const ChannelTrace& trace, const std::vector<double>& residual, double step) {
  const SampleQuantities quantities = DeriveQuantities(trace.measured, step);
  const std::vector<double> speed = Absolute(quantities.velocity);
  const std::vector<bool> high_load = trace.motor_torque.empty()
                                          ? std::vector<bool>(residual.size(), false)
                                          : UpperQuartileAbove(Absolute(trace.motor_torque), kHighLoadFloor);
  return {Regime(kRegimeNames[0], residual, std::vector<bool>(residual.size(), true)),
          Regime(kRegimeNames[1], residual, AtRest(speed)),
          Regime(kRegimeNames[2], residual, HighSpeed(speed)),
          Regime(kRegimeNames[3], residual, NearReversals(quantities.velocity, step)),
          Regime(kRegimeNames[4], residual, high_load),
          Regime(kRegimeNames[5], residual,
                 UpperQuartileAbove(Absolute(quantities.acceleration), kAcceleratingFloor))};
}

// RMS of measured[k] − simulated[k − shift] over the k where both exist; 0 when none do.
double ShiftedRms(const std::vector<double>& measured, const std::vector<double>& simulated, int shift) {
  const long n = static_cast<long>(measured.size());
  const long first = std::max(0L, static_cast<long>(shift));
  const long end = std::min(n, n + shift);
  if (end <= first) return 0.0;
  double sum_of_squares = 0.0;
  for (long k = first; k < end; ++k) {
    const double error = measured[static_cast<std::size_t>(k)] - simulated[static_cast<std::size_t>(k - shift)];
    sum_of_squares += error * error;
  }
  return std::sqrt(sum_of_squares / static_cast<double>(end - first));
}

// Sets best_shift and rms_at_best_shift, trying shifts in order of growing |s| (−s before +s), so that only a
// strictly smaller RMS replaces a smaller shift.
void FindBestShift(const ChannelTrace& trace, double step, ChannelStatistics& statistics) {
  const int n = static_cast<int>(trace.measured.size());
  const int max_shift = std::min(kMaxShift, std::max(0, (n - 1) / 2));
  int best = 0;
  double best_rms = ShiftedRms(trace.measured, trace.simulated, 0);
  for (int size = 1; size <= max_shift; ++size) {
    for (const int shift : {-size, size}) {
      const double rms = ShiftedRms(trace.measured, trace.simulated, shift);
      if (rms < best_rms) {
        best = shift;
        best_rms = rms;
      }
    }
  }
  statistics.best_shift = best * step;
  statistics.rms_at_best_shift = best_rms;
}

}  // namespace

SampleQuantities DeriveQuantities(const std::vector<double>& measured, double step) {
  CheckStep(step);
  SampleQuantities quantities;
  quantities.velocity = LocalSlope(measured, step);
  quantities.acceleration = LocalSlope(quantities.velocity, step);
  return quantities;
}

ChannelStatistics AnalyseChannel(const ChannelTrace& trace, double step) {
  CheckStep(step);
  CheckTrace(trace);
  ChannelStatistics statistics;
  statistics.name = trace.name;
  const std::vector<double> residual = Residual(trace);
  double sum = 0.0;
  for (const double error : residual) {
    sum += error;
    statistics.max_abs = std::max(statistics.max_abs, std::abs(error));
  }
  if (!residual.empty()) statistics.bias = sum / static_cast<double>(residual.size());
  statistics.regimes = Regimes(trace, residual, step);
  statistics.rms = statistics.regimes[0].rms;
  FindBestShift(trace, step, statistics);
  return statistics;
}

double GapRms(const std::vector<ChannelTrace>& traces) {
  double sum_of_squares = 0.0;
  std::size_t samples = 0;
  for (const ChannelTrace& trace : traces) {
    CheckLength(trace, "simulated", trace.simulated.size());
    for (const double error : Residual(trace)) sum_of_squares += error * error;
    samples += trace.measured.size();
  }
  return samples == 0 ? 0.0 : std::sqrt(sum_of_squares / static_cast<double>(samples));
}

double GapMeanAbsolute(const std::vector<ChannelTrace>& traces) {
  double sum = 0.0;
  std::size_t samples = 0;
  for (const ChannelTrace& trace : traces) {
    CheckLength(trace, "simulated", trace.simulated.size());
    for (const double error : Residual(trace)) sum += std::abs(error);
    samples += trace.measured.size();
  }
  return samples == 0 ? 0.0 : sum / static_cast<double>(samples);
}

std::vector<ChannelStatistics> AnalyseChannels(const std::vector<ChannelTrace>& traces, double step) {
  std::vector<ChannelStatistics> statistics;
  statistics.reserve(traces.size());
  for (const ChannelTrace& trace : traces) statistics.push_back(AnalyseChannel(trace, step));
  std::stable_sort(statistics.begin(), statistics.end(),
                   [](const ChannelStatistics& a, const ChannelStatistics& b) { return a.rms > b.rms; });
  return statistics;
}

double Lag1Correlation(const std::vector<double>& series) {
  if (series.size() < 2) return 0.0;
  double mean = 0.0;
  for (double v : series) mean += v;
  mean /= static_cast<double>(series.size());
  double variance = 0.0;
  double covariance = 0.0;
  for (std::size_t i = 0; i < series.size(); ++i) {
    variance += (series[i] - mean) * (series[i] - mean);
    if (i > 0) covariance += (series[i] - mean) * (series[i - 1] - mean);
  }
  return variance > 0.0 ? std::clamp(covariance / variance, 0.0, 0.99) : 0.0;
}

}  // namespace orcs::identify
