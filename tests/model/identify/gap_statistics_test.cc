// The gap workflow's residual statistics, on synthetic traces whose answers are known: offsets, delays,
// dead-band errors at rest, errors at reversals, under load and while accelerating.
#include "model/identify/gap_statistics.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <numbers>
#include <random>
#include <stdexcept>

namespace orcs::identify {
namespace {

using ::testing::HasSubstr;

constexpr double kStep = 0.01;         // s: 100 Hz, as a logged robot run
constexpr double kSensorNoise = 0.19;  // degrees: the measured traces' Gaussian noise
constexpr double kPi = std::numbers::pi;

// f(k·step) for k = 0…n−1.
std::vector<double> Sampled(int n, const std::function<double(double)>& f, double step = kStep) {
  std::vector<double> values(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k) values[static_cast<std::size_t>(k)] = f(k * step);
  return values;
}

std::vector<double> WithNoise(std::vector<double> values, std::uint64_t seed, double sigma = kSensorNoise) {
  std::mt19937_64 random(seed);
  std::normal_distribution<double> noise(0.0, sigma);
  for (double& value : values) value += noise(random);
  return values;
}

ChannelTrace Trace(const std::string& name, std::vector<double> measured, std::vector<double> simulated) {
  ChannelTrace trace;
  trace.name = name;
  trace.desired = simulated;
  trace.measured = std::move(measured);
  trace.simulated = std::move(simulated);
  return trace;
}

const RegimeError& RegimeNamed(const ChannelStatistics& statistics, const std::string& name) {
  for (const RegimeError& regime : statistics.regimes) {
    if (regime.regime == name) return regime;
  }
  throw std::logic_error("no regime " + name);
}

// A triangle wave between −30° and +30° at 60 deg/s, rising from 0 at t = 0: turning points at 0.5 s + k·1 s.
double Triangle(double t) {
  const double phase = std::fmod(t + 0.5, 2.0);  // 0 at the bottom
  return phase < 1.0 ? -30.0 + 60.0 * phase : 30.0 - 60.0 * (phase - 1.0);
}

// Up from −30° to +30° at 60 deg/s in 1 s, 0.5 s still, down in 1 s, 0.5 s still.
double Trapezoid(double t) {
  const double phase = std::fmod(t, 3.0);
  if (phase < 1.0) return -30.0 + 60.0 * phase;
  if (phase < 1.5) return 30.0;
  if (phase < 2.5) return 30.0 - 60.0 * (phase - 1.5);
  return -30.0;
}

// --- DeriveQuantities -----------------------------------------------------------------------------------------

TEST(DeriveQuantitiesTest, ARampHasItsExactSlopeEverywhereEvenAtTheEnds) {
  const SampleQuantities q = DeriveQuantities(Sampled(50, [](double t) { return 3.0 + 30.0 * t; }), kStep);
  ASSERT_EQ(q.velocity.size(), 50u);
  ASSERT_EQ(q.acceleration.size(), 50u);
  for (std::size_t k = 0; k < 50; ++k) {
    EXPECT_NEAR(q.velocity[k], 30.0, 1e-9) << k;
    EXPECT_NEAR(q.acceleration[k], 0.0, 1e-6) << k;
  }
}

TEST(DeriveQuantitiesTest, AParabolaHasItsExactVelocityAndAccelerationAwayFromTheEnds) {
  // x = ½·400·t²: v = 400·t, a = 400. A symmetric window's slope of a parabola is its derivative at the
  // centre; v is exact from sample 5 on, a (the slope of v) from sample 10 on.
  const int n = 100;
  const SampleQuantities q = DeriveQuantities(Sampled(n, [](double t) { return 200.0 * t * t; }), kStep);
  for (int k = 5; k < n - 5; ++k) EXPECT_NEAR(q.velocity[static_cast<std::size_t>(k)], 400.0 * k * kStep, 1e-7) << k;
  for (int k = 10; k < n - 10; ++k) EXPECT_NEAR(q.acceleration[static_cast<std::size_t>(k)], 400.0, 1e-5) << k;
}

TEST(DeriveQuantitiesTest, VelocityOfANoisyRampIsWithinTwoDegreesPerSecond) {
  // Theory: the ±5-sample slope of noise σ has σ/(step·√110) = 1.81 deg/s at 100 Hz; over 30 s the RMS error
  // is within 2 deg/s and the mean error nearly 0.
  const int n = 3000;
  const SampleQuantities q =
      DeriveQuantities(WithNoise(Sampled(n, [](double t) { return 30.0 * t; }), 20080101), kStep);
  double sum = 0.0;
  double sum_of_squares = 0.0;
  for (int k = 5; k < n - 5; ++k) {
    const double error = q.velocity[static_cast<std::size_t>(k)] - 30.0;
    sum += error;
    sum_of_squares += error * error;
  }
  const double interior = n - 10;
  const double theory = kSensorNoise / (kStep * std::sqrt(110.0));
  EXPECT_LT(std::sqrt(sum_of_squares / interior), 2.0);
  EXPECT_NEAR(std::sqrt(sum_of_squares / interior), theory, 0.15 * theory);
  EXPECT_NEAR(sum / interior, 0.0, 0.2);
}

TEST(DeriveQuantitiesTest, ShortTracesAndBadSteps) {
  EXPECT_TRUE(DeriveQuantities({}, kStep).velocity.empty());
  EXPECT_EQ(DeriveQuantities({4.0}, kStep).velocity, std::vector<double>{0.0});
  EXPECT_EQ(DeriveQuantities({1.0, 2.0}, 0.5).velocity, (std::vector<double>{2.0, 2.0}));
  EXPECT_THROW(DeriveQuantities({1.0, 2.0}, 0.0), std::invalid_argument);
  EXPECT_THROW(DeriveQuantities({1.0, 2.0}, -0.01), std::invalid_argument);
  EXPECT_THROW(DeriveQuantities({1.0, 2.0}, std::nan("")), std::invalid_argument);
}

// --- AnalyseChannel: whole-run numbers and the time shift ---------------------------------------------------

TEST(GapStatisticsTest, AConstantOffsetIsTheBiasAndTheRms) {
  const auto sine = [](double t) { return 20.0 * std::sin(2 * kPi * t); };
  const ChannelStatistics s =
      AnalyseChannel(Trace("Right/Knee", Sampled(500, [&](double t) { return sine(t) + 0.7; }), Sampled(500, sine)),
                     kStep);
  EXPECT_EQ(s.name, "Right/Knee");
  EXPECT_NEAR(s.bias, 0.7, 1e-12);
  EXPECT_NEAR(s.rms, 0.7, 1e-12);
  EXPECT_NEAR(s.max_abs, 0.7, 1e-12);
  EXPECT_EQ(s.best_shift, 0.0);  // shifting a sine never cancels an offset
  EXPECT_NEAR(s.rms_at_best_shift, 0.7, 1e-12);
}

TEST(GapStatisticsTest, TimeShiftFindsADelay) {
  const auto sine = [](double t) { return 20.0 * std::sin(2 * kPi * t); };
  const std::vector<double> simulated = Sampled(500, sine);
  const std::vector<double> delayed = Sampled(500, [&](double t) { return sine(t - 0.04); });
  const ChannelStatistics lagging = AnalyseChannel(Trace("Lag", delayed, simulated), kStep);
  EXPECT_NEAR(lagging.best_shift, 0.04, 1e-12);
  EXPECT_LT(lagging.rms_at_best_shift, 1e-9);
  EXPECT_GT(lagging.rms, 3.0);  // 40 ms of a 1 Hz, 20° sine: 20·√2·sin(0.04·π) = 3.5°
  // The other way round the measured trace leads.
  const ChannelStatistics leading = AnalyseChannel(Trace("Lead", simulated, delayed), kStep);
  EXPECT_NEAR(leading.best_shift, -0.04, 1e-12);
  EXPECT_LT(leading.rms_at_best_shift, 1e-9);
}

TEST(GapStatisticsTest, TimeShiftFindsADelayUnderNoise) {
  const auto sine = [](double t) { return 20.0 * std::sin(2 * kPi * t); };
  const ChannelStatistics s = AnalyseChannel(
      Trace("Noisy", WithNoise(Sampled(1000, [&](double t) { return sine(t - 0.12); }), 7), Sampled(1000, sine)),
      kStep);
  EXPECT_NEAR(s.best_shift, 0.12, 1e-12);
  EXPECT_NEAR(s.rms_at_best_shift, kSensorNoise, 0.02);  // only the noise is left
}

TEST(GapStatisticsTest, TimeShiftPrefersTheSmallerShiftOnATieAndStaysInItsRange) {
  const ChannelStatistics still =
      AnalyseChannel(Trace("Still", std::vector<double>(200, 5.0), std::vector<double>(200, 5.0)), kStep);
  EXPECT_EQ(still.best_shift, 0.0);
  EXPECT_EQ(still.rms_at_best_shift, 0.0);
  // A delay of 40 samples is beyond the ±25 searched: the best is the edge of the range, not 40.
  const auto sine = [](double t) { return 20.0 * std::sin(2 * kPi * 0.5 * t); };
  const ChannelStatistics far = AnalyseChannel(
      Trace("Far", Sampled(1000, [&](double t) { return sine(t - 0.4); }), Sampled(1000, sine)), kStep);
  EXPECT_NEAR(far.best_shift, 0.25, 1e-12);
  // A short trace delayed by 2 samples.
  const ChannelStatistics short_trace =
      AnalyseChannel(Trace("Short", {9.0, 9.0, 0.0, 1.0, 2.0}, {0.0, 1.0, 2.0, 3.0, 4.0}), kStep);
  EXPECT_NEAR(short_trace.best_shift, 0.02, 1e-12);
  EXPECT_EQ(short_trace.rms_at_best_shift, 0.0);
  // Shifts of ±4 would match one sample exactly; at most ±2 are tried so that 3 of the 5 overlap.
  const ChannelStatistics ends = AnalyseChannel(Trace("Ends", {5, 0, 0, 0, 7}, {7, 0, 0, 0, 5}), kStep);
  EXPECT_EQ(ends.best_shift, 0.0);
  EXPECT_NEAR(ends.rms_at_best_shift, std::sqrt(8.0 / 5.0), 1e-12);
}

// --- AnalyseChannel: regimes ---------------------------------------------------------------------------------

TEST(GapStatisticsTest, RegimesComeInTheDocumentedOrderWithAllSamplesInAll) {
  const std::vector<double> x = Sampled(300, Triangle);
  const ChannelStatistics s = AnalyseChannel(Trace("J", x, x), kStep);
  ASSERT_EQ(s.regimes.size(), 6u);
  const std::vector<std::string> names = {"all", "at_rest", "high_speed", "reversal", "high_load", "accelerating"};
  for (std::size_t i = 0; i < names.size(); ++i) {
    EXPECT_EQ(s.regimes[i].regime, names[i]);
    EXPECT_EQ(s.regimes[i].regime, kRegimeNames[i]);
  }
  EXPECT_EQ(s.regimes[0].samples, 300);
  EXPECT_EQ(s.regimes[0].share, 1.0);
  for (const RegimeError& regime : s.regimes) EXPECT_EQ(regime.rms, 0.0) << regime.regime;
}

TEST(GapStatisticsTest, ADeadBandErrorAtRestShowsInTheAtRestRegime) {
  // The joint stops 0.5° short of each end (a dead band): the error lives where the trace is still.
  const int n = 1200;
  const std::vector<double> simulated = Sampled(n, Trapezoid);
  const std::vector<double> measured =
      WithNoise(Sampled(n, [](double t) { return std::clamp(Trapezoid(t), -29.5, 29.5); }), 11);
  const ChannelStatistics s = AnalyseChannel(Trace("Dead", measured, simulated), kStep);
  const RegimeError& rest = RegimeNamed(s, "at_rest");
  const RegimeError& fast = RegimeNamed(s, "high_speed");
  ASSERT_GT(rest.samples, 200);  // about 0.4 s of each 1.5 s
  ASSERT_GT(fast.samples, 100);
  EXPECT_NEAR(rest.rms, std::hypot(0.5, kSensorNoise), 0.05);
  EXPECT_NEAR(fast.rms, kSensorNoise, 0.03);
  EXPECT_GT(rest.rms, 2.5 * fast.rms);
  EXPECT_GT(rest.rms, s.rms);
}

TEST(GapStatisticsTest, TheReversalRegimeCoversATenthOfASecondAroundEachReversal) {
  // 10 s of the triangle: 10 turning points, each marking 21 samples (±10 at 100 Hz).
  const std::vector<double> x = Sampled(1000, Triangle);
  const ChannelStatistics s = AnalyseChannel(Trace("J", x, x), kStep);
  const RegimeError& reversal = RegimeNamed(s, "reversal");
  EXPECT_EQ(reversal.samples, 210);
  EXPECT_NEAR(reversal.share, 0.21, 1e-12);
  // The same for a sine through the same turning points: a continuous turn is marked around its turning point.
  const std::vector<double> sine = Sampled(1000, [](double t) { return 30.0 * std::sin(kPi * t); });
  EXPECT_EQ(RegimeNamed(AnalyseChannel(Trace("J", sine, sine), kStep), "reversal").samples, 210);
}

TEST(GapStatisticsTest, AResidualNearReversalsShowsInTheReversalRegime) {
  // A backlash-like bump of 1° within ±50 ms of every turning point (0.5 s + k·1 s).
  const auto bump = [](double t) {
    const double from_turn = std::remainder(t - 0.5, 1.0);
    return std::abs(from_turn) < 0.05 ? std::pow(std::cos(kPi * from_turn / 0.1), 2) : 0.0;
  };
  const int n = 1000;
  const std::vector<double> measured = WithNoise(Sampled(n, [&](double t) { return Triangle(t) + bump(t); }), 3);
  const ChannelStatistics s = AnalyseChannel(Trace("Backlash", measured, Sampled(n, Triangle)), kStep);
  const RegimeError& reversal = RegimeNamed(s, "reversal");
  const RegimeError& fast = RegimeNamed(s, "high_speed");
  // Expected: the bump and the noise over the 21 samples around each true turning point.
  double bump_squares = 0.0;
  for (int k = -10; k <= 10; ++k) bump_squares += std::pow(bump(0.5 + k * kStep), 2);
  EXPECT_NEAR(reversal.rms, std::sqrt(bump_squares / 21 + kSensorNoise * kSensorNoise), 0.05);
  EXPECT_NEAR(reversal.share, 0.21, 0.02);
  EXPECT_NEAR(fast.rms, kSensorNoise, 0.03);  // nothing but noise where the joint moves fastest
  EXPECT_GT(reversal.rms, 2.0 * fast.rms);
  EXPECT_GT(reversal.rms, 1.5 * s.rms);
}

TEST(GapStatisticsTest, APauseBeforeAReversalMarksTheDepartureNotTheWholePause) {
  // Up for 1 s, still for 1 s (noise changes the velocity's sign many times), down for 1 s.
  const auto motion = [](double t) { return t < 1.0 ? 60.0 * t : (t < 2.0 ? 60.0 : 60.0 - 60.0 * (t - 2.0)); };
  const std::vector<double> x = WithNoise(Sampled(300, motion), 5);
  const ChannelStatistics s = AnalyseChannel(Trace("Pause", x, x), kStep);
  const RegimeError& reversal = RegimeNamed(s, "reversal");
  EXPECT_GE(reversal.samples, 20);
  EXPECT_LE(reversal.samples, 21);
  // Which samples: v passes 5 deg/s downwards at about 1.97 s, so the reversal is no earlier than 1.87 s and
  // its samples lie in 1.77…2.07 s, whatever the noise in the pause did to v's sign: a residual of 1 from 1.75 s
  // to 2.2 s captures the whole regime. (The error is put in the simulated trace: the regimes come from the
  // measured one, which stays as it was.)
  std::vector<double> simulated = x;
  for (int k = 175; k <= 220; ++k) simulated[static_cast<std::size_t>(k)] -= 1.0;
  const ChannelStatistics marked = AnalyseChannel(Trace("Pause", x, simulated), kStep);
  EXPECT_NEAR(RegimeNamed(marked, "reversal").rms, 1.0, 1e-12);
}

TEST(GapStatisticsTest, TheHighLoadRegimeHoldsTheLoadedQuarter) {
  // τ = 0.3·sin(2πt) N·m; the residual is 0.5° wherever |τ| ≥ 0.27 N·m, which contains the top quarter of |τ|.
  const int n = 1000;
  const auto torque = [](double t) { return 0.3 * std::sin(2 * kPi * t); };
  const std::vector<double> simulated = Sampled(n, [](double t) { return 20.0 * std::sin(kPi * t); });
  ChannelTrace trace = Trace("Loaded", simulated, simulated);
  trace.motor_torque = Sampled(n, torque);
  for (std::size_t k = 0; k < trace.measured.size(); ++k) {
    if (std::abs(trace.motor_torque[k]) >= 0.27) trace.measured[k] += 0.5;
  }
  const ChannelStatistics s = AnalyseChannel(trace, kStep);
  const RegimeError& load = RegimeNamed(s, "high_load");
  EXPECT_NEAR(load.share, 0.25, 0.01);
  EXPECT_NEAR(load.rms, 0.5, 1e-12);
  EXPECT_NEAR(s.rms, 0.5 * std::sqrt(1.0 - 2.0 / kPi * std::asin(0.9)), 0.01);
}

TEST(GapStatisticsTest, WithoutTorqueOrWithTinyTorqueThereIsNoLoadRegime) {
  const std::vector<double> x = Sampled(300, Triangle);
  ChannelTrace trace = Trace("J", WithNoise(x, 1), x);
  const RegimeError none = RegimeNamed(AnalyseChannel(trace, kStep), "high_load");
  EXPECT_EQ(none.samples, 0);
  EXPECT_EQ(none.rms, 0.0);
  EXPECT_EQ(none.share, 0.0);
  trace.motor_torque = Sampled(300, [](double t) { return 0.04 * std::sin(2 * kPi * t); });
  EXPECT_EQ(RegimeNamed(AnalyseChannel(trace, kStep), "high_load").samples, 0);  // never above 0.05 N·m
}

TEST(GapStatisticsTest, TheAcceleratingRegimeHoldsTheStrongestAccelerations) {
  // An error proportional to the acceleration (a missing rotor inertia): x = 10·sin(2πt) measured as 10.3·sin.
  const int n = 1000;
  const auto x = [](double t) { return 10.0 * std::sin(2 * kPi * t); };
  const ChannelStatistics s =
      AnalyseChannel(Trace("Inertia", Sampled(n, [&](double t) { return 1.03 * x(t); }), Sampled(n, x)), kStep);
  const RegimeError& accelerating = RegimeNamed(s, "accelerating");
  const RegimeError& fast = RegimeNamed(s, "high_speed");
  EXPECT_NEAR(accelerating.share, 0.25, 0.01);  // |a| = 395·|sin| deg/s² ≥ its 75th percentile
  EXPECT_GT(accelerating.rms, 0.28);            // |error| = 0.3·|sin| ≥ 0.3·sin(3π/8) = 0.277 there
  EXPECT_LT(fast.rms, 0.08);                    // and ≤ 0.3·cos(3π/8) = 0.115 where fastest
}

TEST(GapStatisticsTest, SlowMotionIsNeitherHighSpeedNorAccelerating) {
  // 2·sin(πt): at most 6.3 deg/s and 19.7 deg/s², below the 20 deg/s and 200 deg/s² floors.
  const std::vector<double> x = Sampled(1000, [](double t) { return 2.0 * std::sin(kPi * t); });
  const ChannelStatistics s = AnalyseChannel(Trace("Slow", x, x), kStep);
  EXPECT_EQ(RegimeNamed(s, "high_speed").samples, 0);
  EXPECT_EQ(RegimeNamed(s, "accelerating").samples, 0);
  EXPECT_EQ(RegimeNamed(s, "reversal").samples, 0);  // never faster than 10 deg/s, so no direction to reverse
  EXPECT_GT(RegimeNamed(s, "at_rest").samples, 400);
}

TEST(GapStatisticsTest, AnEmptyChannelGivesZeros) {
  const ChannelStatistics s = AnalyseChannel(Trace("Empty", {}, {}), kStep);
  EXPECT_EQ(s.rms, 0.0);
  EXPECT_EQ(s.bias, 0.0);
  EXPECT_EQ(s.best_shift, 0.0);
  ASSERT_EQ(s.regimes.size(), 6u);
  for (const RegimeError& regime : s.regimes) EXPECT_EQ(regime.samples, 0);
}

TEST(GapStatisticsTest, RejectsTracesOfDifferentLengthsNamingTheChannel) {
  ChannelTrace trace = Trace("Left/Ankle", {1.0, 2.0, 3.0}, {1.0, 2.0});
  try {
    AnalyseChannel(trace, kStep);
    FAIL() << "no exception";
  } catch (const std::invalid_argument& error) {
    EXPECT_THAT(error.what(), HasSubstr("Left/Ankle"));
    EXPECT_THAT(error.what(), HasSubstr("3 measured samples but 2 simulated"));
  }
  trace.simulated.push_back(3.0);
  trace.desired = trace.simulated;
  trace.motor_torque = {0.1};
  EXPECT_THROW(AnalyseChannel(trace, kStep), std::invalid_argument);
  trace.motor_torque.clear();
  trace.desired.clear();  // the commands are not needed here
  EXPECT_NO_THROW(AnalyseChannel(trace, kStep));
  EXPECT_THROW(AnalyseChannel(trace, 0.0), std::invalid_argument);
  trace.measured[1] = std::nan("");
  try {
    AnalyseChannel(trace, kStep);
    FAIL() << "no exception";
  } catch (const std::invalid_argument& error) {
    EXPECT_THAT(error.what(), HasSubstr("Left/Ankle: measured sample 1 is not a finite number"));
  }
  EXPECT_THROW(GapRms({Trace("Bad", {1.0}, {})}), std::invalid_argument);
}

// --- Several channels ----------------------------------------------------------------------------------------

TEST(GapStatisticsTest, AnalyseChannelsSortsWorstFirst) {
  const std::vector<double> x = Sampled(200, Triangle);
  const auto offset = [&](double by) {
    std::vector<double> shifted = x;
    for (double& value : shifted) value += by;
    return shifted;
  };
  const std::vector<ChannelStatistics> s = AnalyseChannels(
      {Trace("A", offset(0.1), x), Trace("B", offset(-0.9), x), Trace("C", offset(0.4), x)}, kStep);
  ASSERT_EQ(s.size(), 3u);
  EXPECT_EQ(s[0].name, "B");
  EXPECT_EQ(s[1].name, "C");
  EXPECT_EQ(s[2].name, "A");
  EXPECT_NEAR(s[0].rms, 0.9, 1e-12);
  EXPECT_NEAR(s[0].bias, -0.9, 1e-12);
  EXPECT_TRUE(AnalyseChannels({}, kStep).empty());
}

TEST(GapStatisticsTest, GapRmsPoolsAllSamplesOfAllChannels) {
  // 100 samples 1° off and 300 samples 3° off: √((100·1 + 300·9)/400) = √7, not the mean of the RMS (2).
  const ChannelTrace a = Trace("A", std::vector<double>(100, 1.0), std::vector<double>(100, 0.0));
  const ChannelTrace b = Trace("B", std::vector<double>(300, -3.0), std::vector<double>(300, 0.0));
  EXPECT_NEAR(GapRms({a, b}), std::sqrt(7.0), 1e-12);
  EXPECT_NEAR(GapRms({a}), 1.0, 1e-12);
  EXPECT_EQ(GapRms({}), 0.0);
}

TEST(GapStatisticsTest, GapMeanAbsolutePoolsTheSizesOfTheErrorsWhateverTheirSign) {
  // The same traces: (100·1 + 300·3)/400 = 2.5°, below the RMS √7 = 2.65° (the RMS weighs the large errors more).
  const ChannelTrace a = Trace("A", std::vector<double>(100, 1.0), std::vector<double>(100, 0.0));
  const ChannelTrace b = Trace("B", std::vector<double>(300, -3.0), std::vector<double>(300, 0.0));
  EXPECT_NEAR(GapMeanAbsolute({a, b}), 2.5, 1e-12);
  EXPECT_NEAR(GapMeanAbsolute({Trace("C", {1.0, 2.0, 3.0}, {0.0, 2.0, 5.0})}), 1.0, 1e-12);
  EXPECT_EQ(GapMeanAbsolute({}), 0.0);
  EXPECT_THROW(GapMeanAbsolute({Trace("Bad", {1.0}, {})}), std::invalid_argument);
}

// The lag-1 correlation that widens the confidence intervals (least_squares_polish.h): near 0 for white noise,
// near the AR(1) coefficient for a drifting series, and clamped to [0, 0.99].
TEST(GapStatisticsTest, Lag1CorrelationOfWhiteAndOfDriftingSeries) {
  std::mt19937 engine(49);
  std::normal_distribution<double> noise(0.0, 1.0);
  std::vector<double> white(4000), drift(4000), alternating(4000);
  double walk = 0.0;
  for (std::size_t i = 0; i < white.size(); ++i) {
    white[i] = noise(engine);
    walk = 0.95 * walk + noise(engine);
    drift[i] = walk;
    alternating[i] = i % 2 == 0 ? 1.0 : -1.0;
  }
  EXPECT_NEAR(Lag1Correlation(white), 0.0, 0.05);
  EXPECT_NEAR(Lag1Correlation(drift), 0.95, 0.02);
  EXPECT_EQ(Lag1Correlation(alternating), 0.0);  // negative correlation counts as none
  EXPECT_EQ(Lag1Correlation(std::vector<double>(100, 3.0)), 0.0);
  EXPECT_EQ(Lag1Correlation({1.0}), 0.0);
}

}  // namespace
}  // namespace orcs::identify
