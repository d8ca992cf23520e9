// The residual statistics of the gap workflow (orcs-gap): where a simulated replay of a robot's commands
// disagrees with the measured joint angles. Per channel (one joint) the residual measured − simulated is
// summarised as a whole (RMS, largest error, bias), inside regimes of the motion (at rest, fast, reversing,
// loaded, accelerating: each physical effect the model may lack leaves its error in some of them), and after
// the time shift that fits best (a transport delay shows up as a shift, not as a regime).
//
// Regimes, from the measured trace's velocity v and acceleration a (DeriveQuantities) and the simulated motor
// torque τ; percentiles interpolate linearly between the sorted values (numpy's default):
//   all           every sample
//   at_rest       |v| < 5 deg/s
//   high_speed    |v| ≥ max(20 deg/s, 75th percentile of |v|)
//   reversal      |t − t_r| ≤ 0.1 s of a reversal time t_r: where v changes sign between a stretch with
//                 |v| > 10 deg/s in one direction and the next such stretch in the other direction. When v
//                 changes sign more than once in between, t_r is the last change, the one after which v keeps
//                 the new direction, but no earlier than 0.1 s before v last rose through 5 deg/s in the new
//                 direction: in a pause v's sign is noise (σ_v ≈ 1.8 deg/s at 100 Hz) and may have turned long
//                 before the joint departs, and the departure is where backlash and sticking show. Crossings are
//                 interpolated linearly between samples. A continuous turn with |a| ≥ 50 deg/s² there (5 deg/s
//                 within 0.1 s) has t_r at its turning point.
//   high_load     |τ| ≥ 75th percentile of |τ| and |τ| > 0.05 N·m; no samples when the torque is not known
//   accelerating  |a| ≥ 75th percentile of |a| and |a| > 200 deg/s²
// Regimes overlap (a reversal is also slow and accelerating); each one's RMS is over its own samples.
//
// Time shift: integer shifts s in [−25, +25] samples (and |s| ≤ (n − 1)/2, so that at least half of a short
// trace overlaps), comparing measured[k] with simulated[k − s] on the overlap; the smallest RMS wins, ties
// go to the smaller |s| (then to the negative s). Positive s: the measured trace lags the simulated one.
#pragma once

#include <array>
#include <string>
#include <string_view>
#include <vector>

namespace orcs::identify {

/// One joint's traces on a common time base (row k at k·step), all the same length.
struct ChannelTrace {
  std::string name;                  ///< motor name, e.g. "Right/Knee"
  std::vector<double> measured;      ///< measured joint angle, degrees
  std::vector<double> simulated;     ///< simulated joint angle, degrees
  std::vector<double> desired;       ///< commanded angle, degrees
  std::vector<double> motor_torque;  ///< simulated motor torque, N·m (may be empty: then no load regime)
};

/// Where an error happens: one regime of the motion and the error inside it.
struct RegimeError {
  std::string regime;  ///< "all", "at_rest", "high_speed", "reversal", "high_load", "accelerating"
  double rms = 0.0;    ///< RMS of measured − simulated over the regime's samples, degrees (0 if none)
  double share = 0.0;  ///< fraction of the run's samples in the regime, 0…1
  int samples = 0;     ///< number of samples in the regime
};

/// The residual measured − simulated of one channel, summarised.
struct ChannelStatistics {
  std::string name;                  ///< the channel's motor name (ChannelTrace::name)
  double rms = 0.0;                  ///< degrees, over all samples
  double max_abs = 0.0;              ///< largest |measured − simulated|, degrees
  double bias = 0.0;                 ///< mean of measured − simulated, degrees
  std::vector<RegimeError> regimes;  ///< in the order listed above (kRegimeNames)
  double best_shift = 0.0;           ///< s; the shift of the simulated trace that minimises the RMS
                                     ///< (positive: measured lags)
  double rms_at_best_shift = 0.0;    ///< RMS over the overlap at best_shift, degrees
};

/// Per-sample quantities derived from the measured trace, used for regimes and by the residual plots.
struct SampleQuantities {
  std::vector<double> velocity;      ///< deg/s, local least-squares slope of `measured` over ±5 samples
                                     ///< (clamped at the ends)
  std::vector<double> acceleration;  ///< deg/s², slope of `velocity` the same way
};

/// The regimes' names, in the order of ChannelStatistics::regimes.
inline constexpr std::array<std::string_view, 6> kRegimeNames = {"all",      "at_rest",   "high_speed",
                                                                 "reversal", "high_load", "accelerating"};

/// Velocity and acceleration of `measured` sampled every `step` seconds. The ±5-sample window averages the
/// sensor noise (σ ≈ 0.19° gives σ_v ≈ 0.19°/(step·√110), 1.8 deg/s at 100 Hz); near the ends it is cut to the
/// samples there are, so a straight line still gives its exact slope. Throws std::invalid_argument when step
/// is not a positive finite number.
SampleQuantities DeriveQuantities(const std::vector<double>& measured, double step);

/// The statistics of one channel sampled every `step` seconds. Throws std::invalid_argument (naming the
/// channel) when the traces differ in length (desired, unused here, and motor_torque may be empty), when a
/// measured, simulated or torque sample is not a finite number, or when step is not positive and finite.
/// An empty channel gives zeros.
ChannelStatistics AnalyseChannel(const ChannelTrace& trace, double step);

/// RMS of measured − simulated over all samples of all traces together (the "gap"), degrees; 0 with no samples.
/// Throws std::invalid_argument when a trace's measured and simulated differ in length.
double GapRms(const std::vector<ChannelTrace>& traces);

/// Mean of |measured − simulated| over all samples of all traces together, degrees (the BAM project's mean absolute
/// position error, which it reports in mrad); 0 with no samples. Throws as GapRms.
double GapMeanAbsolute(const std::vector<ChannelTrace>& traces);

/// The channels sorted by rms, worst first (equal rms keep the traces' order).
std::vector<ChannelStatistics> AnalyseChannels(const std::vector<ChannelTrace>& traces, double step);

/// The lag-1 autocorrelation of a series, clamped to [0, 0.99]: how much each sample repeats the one before. 0 for
/// fewer than two samples or no variance.
double Lag1Correlation(const std::vector<double>& series);


}  // namespace orcs::identify
