#include "model/aseries/accelerometer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "model/core/random_stream.h"
#include "model/core/rotation.h"
#include "model/core/variable_repository.h"

namespace orcs::aseries {
namespace {

constexpr double kDt = 0.01;
constexpr double kG = 9.81;

void ExpectVectorNear(const Eigen::Vector3d& actual, const Eigen::Vector3d& expected) {
  EXPECT_NEAR((actual - expected).norm(), 0.0, 1e-6) << "actual (" << actual.transpose() << "), expected ("
                                                      << expected.transpose() << ")";
}

AccelerometerParameters NoNoise() {
  AccelerometerParameters parameters;
  parameters.deviation = 0.0;
  return parameters;
}

// A board whose Axis1 is the host's x and Axis2 the host's y, off the host's origin.
AccelerometerBoard XyBoard() {
  AccelerometerBoard board;
  board.local_position = {0.01, 0.02, 0.03};
  board.axes = {Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY()};
  return board;
}

// Moves a host body with a given acceleration in each step (semi-implicit Euler, as the measured finite
// differences invert it exactly): the board then measures that acceleration from the step on.
class Trajectory {
 public:
  Trajectory(const AccelerometerParameters& parameters, const AccelerometerBoard& board,
             const Eigen::Quaterniond& rotation = Eigen::Quaterniond::Identity())
      : parameters_(parameters), board_(board), rotation_(rotation) {
    Reset(state_, board_, position_, rotation_);
  }
  std::array<double, 2> Step(const Eigen::Vector3d& acceleration, RandomStream* noise = nullptr) {
    velocity_ += acceleration * kDt;
    position_ += velocity_ * kDt;
    return Measure(parameters_, board_, state_, position_, rotation_, kDt, noise);
  }
  std::array<double, 2> Step(double ax, double ay) { return Step(Eigen::Vector3d(ax, ay, 0.0)); }
  AccelerometerState& state() { return state_; }

 private:
  AccelerometerParameters parameters_;
  AccelerometerBoard board_;
  Eigen::Quaterniond rotation_;
  Eigen::Vector3d position_{0.1, 0.2, 0.3};
  Eigen::Vector3d velocity_ = Eigen::Vector3d::Zero();
  AccelerometerState state_{};
};

TEST(AccelerometerTest, Defaults) {
  const AccelerometerParameters p;
  EXPECT_EQ(p.deviation, 0.0001);
  EXPECT_EQ(p.low_pass_filter_delay, 1);
  EXPECT_EQ(p.gravity, 9.81);
  EXPECT_EQ(p.cut_off, 11.772);
  EXPECT_EQ(p.range, 16.072704);
}

TEST(AccelerometerTest, BoardAxesFromThePlacementTable) {
  // Spec §5: local rotation (NERD degrees) → Axis1, Axis2 in the host frame.
  struct Row {
    Eigen::Vector3d euler, axis1, axis2;
  };
  const std::vector<Row> rows = {
      {{0, 90, 0}, {1, 0, 0}, {0, 0, -1}},   // ABFR
      {{0, 0, 90}, {0, 0, 1}, {0, 1, 0}},    // ABHR
      {{0, 0, 0}, {0, 0, 1}, {1, 0, 0}},     // ABSR, ABML
      {{-90, 0, 0}, {0, 1, 0}, {1, 0, 0}},   // ABAR, ABAL
      {{0, -90, 0}, {-1, 0, 0}, {0, 0, 1}},  // ABFL
      {{0, 0, -90}, {0, 0, 1}, {0, -1, 0}},  // ABHL
  };
  for (const Row& row : rows) {
    const AccelerometerBoard board =
        MakeAccelerometerBoard(Eigen::Vector3d(0.1, 0.2, 0.3), QuaternionFromEulerDegrees(row.euler));
    ExpectVectorNear(board.axes[0], row.axis1);
    ExpectVectorNear(board.axes[1], row.axis2);
    EXPECT_EQ(board.local_position, Eigen::Vector3d(0.1, 0.2, 0.3));
  }
  // The table's quaternion (w, x, y, z) of ABFR gives the same.
  const AccelerometerBoard abfr =
      MakeAccelerometerBoard(Eigen::Vector3d(0.0072, 0.01445, 0.03005), Eigen::Quaterniond(0.707107, 0, 0.707107, 0));
  ExpectVectorNear(abfr.axes[0], {1, 0, 0});
  ExpectVectorNear(abfr.axes[1], {0, 0, -1});
}

TEST(AccelerometerTest, AtRestAnUpwardAxisReadsMinusG) {
  // Spec §5 expected readings in the initial pose: ABHR Axis2 = −9.81, ABHL Axis2 = +9.81,
  // ABAR Axis1 = −9.81, ABFR both 0.
  const AccelerometerParameters p = NoNoise();
  const Eigen::Quaterniond identity = Eigen::Quaterniond::Identity();
  const Eigen::Vector3d host(-0.03225, 0.146, -0.0105);
  struct Case {
    Eigen::Vector3d euler;
    double axis1, axis2;
  };
  for (const Case& c : std::vector<Case>{{{0, 0, 90}, 0.0, -kG},   // ABHR
                                         {{0, 0, -90}, 0.0, kG},   // ABHL
                                         {{-90, 0, 0}, -kG, 0.0},  // ABAR
                                         {{0, 90, 0}, 0.0, 0.0}}) {  // ABFR
    const AccelerometerBoard board =
        MakeAccelerometerBoard({-0.0443, 0.0015, -0.00681}, QuaternionFromEulerDegrees(c.euler));
    AccelerometerState state{};
    Reset(state, board, host, identity);
    for (int i = 0; i < 3; ++i) {
      const std::array<double, 2> reading = Measure(p, board, state, host, identity, kDt, nullptr);
      EXPECT_NEAR(reading[0], c.axis1, 1e-12);
      EXPECT_NEAR(reading[1], c.axis2, 1e-12);
    }
  }
}

TEST(AccelerometerTest, HostRotationTurnsTheAxes) {
  // Host turned 90° about z: its x axis points up (reads −g), its y axis along world −x (reads 0).
  const Eigen::Quaterniond turned(Eigen::AngleAxisd(std::numbers::pi / 2, Eigen::Vector3d::UnitZ()));
  Trajectory trajectory(NoNoise(), XyBoard(), turned);
  const std::array<double, 2> reading = trajectory.Step(0.0, 0.0);
  EXPECT_NEAR(reading[0], -kG, 1e-9);
  EXPECT_NEAR(reading[1], 0.0, 1e-9);
  // Turned the other way, host x points down and reads +g.
  Trajectory upside(NoNoise(), XyBoard(), Eigen::Quaterniond(Eigen::AngleAxisd(-std::numbers::pi / 2,
                                                                               Eigen::Vector3d::UnitZ())));
  EXPECT_NEAR(upside.Step(0.0, 0.0)[0], kG, 1e-9);
}

TEST(AccelerometerTest, ConstantAccelerationAfterTheDifferencesSettle) {
  // a = (1, 1.5, −3) m/s² from rest, moved by semi-implicit Euler (v += a·dt, p += v·dt), which the two
  // backward differences invert exactly: every sample reads −(a + g·ŷ)·axis. (The exact parabola below shows
  // the first-sample transient.)
  Trajectory trajectory(NoNoise(), XyBoard());
  const Eigen::Vector3d a(1.0, 1.5, -3.0);
  std::array<double, 2> reading = trajectory.Step(a);
  EXPECT_NEAR(reading[0], -1.0, 1e-6);
  EXPECT_NEAR(reading[1], -(1.5 + kG), 1e-6);
  for (int i = 0; i < 20; ++i) {
    reading = trajectory.Step(a);
    EXPECT_NEAR(reading[0], -1.0, 1e-6);
    EXPECT_NEAR(reading[1], -(1.5 + kG), 1e-6);
  }
}

TEST(AccelerometerTest, ConstantAccelerationOfAnExactParabola) {
  // p(t) = p0 + ½·a·t², sampled exactly: the first sample sees a/2, the following ones a.
  const AccelerometerParameters p = NoNoise();
  const AccelerometerBoard board = XyBoard();
  const Eigen::Quaterniond turned(Eigen::AngleAxisd(std::numbers::pi / 2, Eigen::Vector3d::UnitZ()));  // host x is world y
  const Eigen::Vector3d p0(0.5, 0.25, -0.125);
  const Eigen::Vector3d a(2.0, -1.0, 0.5);  // world
  AccelerometerState state{};
  Reset(state, board, p0, turned);
  for (int k = 1; k <= 10; ++k) {
    const double t = k * kDt;
    const std::array<double, 2> reading = Measure(p, board, state, p0 + 0.5 * a * t * t, turned, kDt, nullptr);
    const double scale = k == 1 ? 0.5 : 1.0;
    // Axis1 = host x = world y: −(a_y·scale + g); Axis2 = host y = world −x: +a_x·scale.
    EXPECT_NEAR(reading[0], -(scale * a.y() + kG), 1e-6) << "k = " << k;
    EXPECT_NEAR(reading[1], scale * a.x(), 1e-6) << "k = " << k;
  }
}

TEST(AccelerometerTest, CutOffHoldsBothAxesUntilBothAreBackInRange) {
  Trajectory trajectory(NoNoise(), XyBoard());
  std::array<double, 2> reading = trajectory.Step(0.0, 0.0);
  EXPECT_NEAR(reading[0], 0.0, 1e-6);
  EXPECT_NEAR(reading[1], -kG, 1e-6);
  const std::array<double, 2> valid = trajectory.Step(1.0, 0.5);
  EXPECT_NEAR(valid[0], -1.0, 1e-6);
  EXPECT_NEAR(valid[1], -10.31, 1e-6);
  // Axis 1 spikes to +20 (axis 2 would read −8.81, in range): both axes keep the last valid pair.
  reading = trajectory.Step(-20.0, -1.0);
  EXPECT_EQ(reading, valid);
  // Axis 1 back in range (−5) but axis 2 now out (−12.31): still held.
  reading = trajectory.Step(5.0, 2.5);
  EXPECT_EQ(reading, valid);
  // A negative spike on axis 1 also counts (|−12| > 11.772).
  reading = trajectory.Step(12.0, 0.0);
  EXPECT_EQ(reading, valid);
  // Both in range again: measuring resumes.
  reading = trajectory.Step(2.0, -2.0);
  EXPECT_NEAR(reading[0], -2.0, 1e-6);
  EXPECT_NEAR(reading[1], -7.81, 1e-6);
  reading = trajectory.Step(0.0, 0.0);
  EXPECT_NEAR(reading[0], 0.0, 1e-6);
  EXPECT_NEAR(reading[1], -kG, 1e-6);
}

TEST(AccelerometerTest, CutOffHoldsZeroBeforeAnyValidPair) {
  Trajectory trajectory(NoNoise(), XyBoard());
  EXPECT_EQ(trajectory.Step(30.0, 0.0), (std::array<double, 2>{0.0, 0.0}));
}

TEST(AccelerometerTest, MovingAverageDividesByTheSamplesInTheWindow) {
  AccelerometerParameters p = NoNoise();
  p.low_pass_filter_delay = 3;
  Trajectory trajectory(p, XyBoard());
  // Axis 1 readings 3, 6, 9, 0, −3, then a spike that holds −3.
  const std::vector<double> ax = {-3.0, -6.0, -9.0, 0.0, 3.0, 50.0};
  const std::vector<double> expected = {3.0,                  // 3/1 (NERD's /N would give 1)
                                        4.5,                  // (3+6)/2 (NERD: 3)
                                        6.0,                  // (3+6+9)/3
                                        5.0,                  // (6+9+0)/3
                                        2.0,                  // (9+0−3)/3
                                        -2.0};                // (0−3−3)/3: the held value enters the window
  for (std::size_t i = 0; i < ax.size(); ++i) {
    const std::array<double, 2> reading = trajectory.Step(ax[i], 0.0);
    EXPECT_NEAR(reading[0], expected[i], 1e-6) << "step " << i;
    EXPECT_NEAR(reading[1], -kG, 1e-6) << "step " << i;
  }
  // A reset empties the window.
  trajectory = Trajectory(p, XyBoard());
  EXPECT_NEAR(trajectory.Step(-4.0, 0.0)[0], 4.0, 1e-6);
}

TEST(AccelerometerTest, WindowIsClampedToItsCapacity) {
  AccelerometerParameters p = NoNoise();
  p.low_pass_filter_delay = 1000;
  Trajectory trajectory(p, XyBoard());
  std::array<double, 2> reading{};
  // 64 samples of axis 1 = 1, then 64 of 0 go in: the mean over the last 64 is 0, over 128 it would be 0.5.
  for (int i = 0; i < 64; ++i) reading = trajectory.Step(-1.0, 0.0);
  EXPECT_NEAR(reading[0], 1.0, 1e-6);
  for (int i = 0; i < 64; ++i) reading = trajectory.Step(0.0, 0.0);
  EXPECT_NEAR(reading[0], 0.0, 1e-6);
}

TEST(AccelerometerTest, WithoutResetTheFirstSampleSeesNoMotion) {
  const AccelerometerParameters p = NoNoise();
  const AccelerometerBoard board = XyBoard();
  AccelerometerState state{};  // never reset: p_prev unknown
  const Eigen::Quaterniond identity = Eigen::Quaterniond::Identity();
  std::array<double, 2> reading = Measure(p, board, state, {1.0, 2.0, 3.0}, identity, kDt, nullptr);
  EXPECT_NEAR(reading[0], 0.0, 1e-9);
  EXPECT_NEAR(reading[1], -kG, 1e-9);
  reading = Measure(p, board, state, {1.0, 2.0, 3.0}, identity, kDt, nullptr);
  EXPECT_NEAR(reading[1], -kG, 1e-9);
}

TEST(AccelerometerTest, GravityComesFromTheParameters) {
  AccelerometerParameters p = NoNoise();
  p.gravity = 1.62;
  Trajectory trajectory(p, XyBoard());
  EXPECT_NEAR(trajectory.Step(0.0, 0.0)[1], -1.62, 1e-9);
}

TEST(AccelerometerTest, NoiseIsReproducibleAndComesAfterTheFilter) {
  AccelerometerParameters p;  // σ = 0.0001
  p.low_pass_filter_delay = 2;
  Trajectory trajectory(p, XyBoard());
  RandomStream stream(21, "accel-noise", 4);
  RandomStream expected = stream;
  std::array<double, 2> reading = trajectory.Step(Eigen::Vector3d(-2.0, 0.0, 0.0), &stream);
  EXPECT_NEAR(reading[0], 2.0 + expected.Normal(0.0, 0.0001), 1e-9);
  EXPECT_NEAR(reading[1], -kG + expected.Normal(0.0, 0.0001), 1e-9);
  // The window holds noise-free values: (2 + 4)/2 = 3, plus a fresh draw.
  reading = trajectory.Step(Eigen::Vector3d(-4.0, 0.0, 0.0), &stream);
  EXPECT_NEAR(reading[0], 3.0 + expected.Normal(0.0, 0.0001), 1e-9);
  EXPECT_NEAR(reading[1], -kG + expected.Normal(0.0, 0.0001), 1e-9);
}

TEST(AccelerometerTest, NoiseHasTheRightMeanAndDeviation) {
  AccelerometerParameters p;
  p.deviation = 0.05;
  Trajectory trajectory(p, XyBoard());
  RandomStream stream(23, "accel-noise", 0);
  constexpr int kSamples = 20000;
  double sum[2] = {0, 0}, sum_squares[2] = {0, 0};
  for (int i = 0; i < kSamples; ++i) {
    const std::array<double, 2> reading = trajectory.Step(Eigen::Vector3d::Zero(), &stream);
    for (int axis = 0; axis < 2; ++axis) {
      sum[axis] += reading[axis];
      sum_squares[axis] += reading[axis] * reading[axis];
    }
  }
  const double expected_mean[2] = {0.0, -kG};
  for (int axis = 0; axis < 2; ++axis) {
    const double mean = sum[axis] / kSamples;
    const double deviation = std::sqrt(sum_squares[axis] / kSamples - mean * mean);
    EXPECT_NEAR(mean, expected_mean[axis], 4 * 0.05 / std::sqrt(kSamples)) << "axis " << axis;
    EXPECT_NEAR(deviation, 0.05, 0.02 * 0.05) << "axis " << axis;
  }
}

TEST(AccelerometerTest, NoiseOffWithoutStreamOrDeviation) {
  AccelerometerParameters p;
  p.deviation = 0.0;
  RandomStream stream(1, "accel-noise", 0);
  const RandomStream untouched = stream;
  Trajectory trajectory(p, XyBoard());
  EXPECT_NEAR(trajectory.Step(Eigen::Vector3d::Zero(), &stream)[1], -kG, 1e-9);
  RandomStream copy = untouched;
  EXPECT_EQ(stream.NextU64(), copy.NextU64());
  Trajectory with_default(AccelerometerParameters{}, XyBoard());
  EXPECT_NEAR(with_default.Step(Eigen::Vector3d::Zero(), nullptr)[1], -kG, 1e-9);
}

TEST(AccelerometerTest, OutputIsClampedToTheRange) {
  AccelerometerParameters p;
  p.deviation = 20.0;  // huge noise pushes readings past ±16.072704
  Trajectory trajectory(p, XyBoard());
  RandomStream stream(29, "accel-noise", 0);
  int at_bound = 0;
  for (int i = 0; i < 200; ++i) {
    for (double value : trajectory.Step(Eigen::Vector3d::Zero(), &stream)) {
      EXPECT_LE(std::abs(value), 16.072704);
      if (std::abs(value) == 16.072704) ++at_bound;
    }
  }
  EXPECT_GT(at_bound, 0);
}

TEST(AccelerometerParameterTableTest, ReadsTheRepository) {
  VariableRepository repository;
  AddParameters(repository, kAccelerometerParameterTable);
  AddParameters(repository, kAccelerometerGravityTable);
  EXPECT_EQ(repository.Get("/AccelSensor/Deviation").as_double(), 0.0001);
  EXPECT_EQ(repository.Get("/AccelSensor/LowPassFilterDelay").as_int(), 1);
  EXPECT_EQ(repository.Get("/AccelSensor/CutOff").as_double(), 11.772) << "1.2 g, the board's cut-off";
  EXPECT_EQ(repository.Get("/AccelSensor/Range").as_double(), 16.072704) << "±1.6384 g, its output range";
  repository.Set("/AccelSensor/LowPassFilterDelay", "3");
  repository.Set("/AccelSensor/Range", "9.81");
  repository.Set("/Simulation/Gravitation", "1.62");
  AccelerometerParameters p;
  ReadParameters(repository, kAccelerometerParameterTable, p);
  ReadParameters(repository, kAccelerometerGravityTable, p);
  EXPECT_EQ(p.low_pass_filter_delay, 3);
  EXPECT_EQ(p.range, 9.81);
  EXPECT_EQ(p.gravity, 1.62);
}

}  // namespace
}  // namespace orcs::aseries
