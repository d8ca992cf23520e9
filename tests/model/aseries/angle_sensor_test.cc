#include "model/aseries/angle_sensor.h"

#include <gtest/gtest.h>

#include <cmath>

#include "model/core/random_stream.h"
#include "model/core/rotation.h"
#include "model/core/variable_repository.h"

namespace orcs::aseries {
namespace {

constexpr double kTight = 1e-12;

AngleSensorParameters NoNoise() {
  AngleSensorParameters parameters;
  parameters.include_noise = false;
  return parameters;
}

TEST(AngleSensorTest, Defaults) {
  const AngleSensorParameters p;
  EXPECT_EQ(p.noise_deviation, 0.189076);
  EXPECT_TRUE(p.include_noise);  // quirk 9: the intended default, noise on
  EXPECT_EQ(p.min_angle, -150.0);
  EXPECT_EQ(p.max_angle, 150.0);
}

TEST(AngleSensorTest, ConvertsRadiansToDegrees) {
  RandomStream stream(1, "sensor-noise", 0);
  EXPECT_NEAR(MeasureJointAngle(0.5, NoNoise(), &stream), 28.64788975654116, kTight);
  EXPECT_NEAR(MeasureJointAngle(-1.0, NoNoise(), &stream), -57.29577951308232, kTight);
  EXPECT_EQ(MeasureJointAngle(0.0, NoNoise(), &stream), 0.0);
}

TEST(AngleSensorTest, ClampsToTheSensorRange) {
  EXPECT_EQ(MeasureJointAngle(3.0, NoNoise(), nullptr), 150.0);   // 171.9°
  EXPECT_EQ(MeasureJointAngle(-3.0, NoNoise(), nullptr), -150.0);
  AngleSensorParameters narrow = NoNoise();
  narrow.min_angle = -10.0;
  narrow.max_angle = 20.0;
  EXPECT_EQ(MeasureJointAngle(0.5, narrow, nullptr), 20.0);
  EXPECT_EQ(MeasureJointAngle(-0.5, narrow, nullptr), -10.0);
}

TEST(AngleSensorTest, NoiseOffDrawsNothing) {
  RandomStream stream(3, "sensor-noise", 2);
  const RandomStream untouched = stream;
  for (int i = 0; i < 10; ++i) EXPECT_NEAR(MeasureJointAngle(0.5, NoNoise(), &stream), 28.64788975654116, kTight);
  RandomStream copy = untouched;
  EXPECT_EQ(stream.NextU64(), copy.NextU64());
  // Noise on but no stream, or deviation 0: also exact.
  AngleSensorParameters p;
  EXPECT_NEAR(MeasureJointAngle(0.5, p, nullptr), 28.64788975654116, kTight);
  p.noise_deviation = 0.0;
  EXPECT_NEAR(MeasureJointAngle(0.5, p, &stream), 28.64788975654116, kTight);
}

TEST(AngleSensorTest, NoiseIsReproducible) {
  const AngleSensorParameters p;
  RandomStream stream(5, "sensor-noise", 7);
  RandomStream expected = stream;
  for (int i = 0; i < 5; ++i) {
    EXPECT_DOUBLE_EQ(MeasureJointAngle(0.5, p, &stream), 28.64788975654116 + expected.Normal(0.0, 0.189076));
  }
}

TEST(AngleSensorTest, NoiseHasTheRightMeanAndDeviation) {
  const AngleSensorParameters p;
  RandomStream stream(9, "sensor-noise", 0);
  constexpr int kSamples = 20000;
  const double angle = DegreesToRadians(10.0);
  double sum = 0.0, sum_squares = 0.0;
  for (int i = 0; i < kSamples; ++i) {
    const double reading = MeasureJointAngle(angle, p, &stream);
    sum += reading;
    sum_squares += reading * reading;
  }
  const double mean = sum / kSamples;
  const double deviation = std::sqrt(sum_squares / kSamples - mean * mean);
  EXPECT_NEAR(mean, 10.0, 4 * 0.189076 / std::sqrt(kSamples));
  EXPECT_NEAR(deviation, 0.189076, 0.02 * 0.189076);
}

TEST(AngleSensorTest, NoiseIsClampedAtTheRangeEnd) {
  const AngleSensorParameters p;
  RandomStream stream(13, "sensor-noise", 0);
  const double angle = DegreesToRadians(150.0);
  int at_limit = 0;
  for (int i = 0; i < 1000; ++i) {
    const double reading = MeasureJointAngle(angle, p, &stream);
    EXPECT_LE(reading, 150.0);
    EXPECT_GT(reading, 149.0);
    if (reading == 150.0) ++at_limit;
  }
  // About half the draws are positive and end at the limit.
  EXPECT_GT(at_limit, 400);
  EXPECT_LT(at_limit, 600);
}

TEST(AngleSensorParameterTableTest, SharesTheNoiseSwitchWithTheMotor) {
  VariableRepository repository;
  AddParameters(repository, kAngleSensorParameterTable);
  EXPECT_EQ(repository.Get("/AngularMotor/SensorNoiseDeviation").as_double(), 0.189076);
  repository.Set("/AngularMotor/IncludeNoise", "F");
  repository.Set("/AngularMotor/SensorNoiseDeviation", "0.5");
  AngleSensorParameters p;
  ReadParameters(repository, kAngleSensorParameterTable, p);
  EXPECT_FALSE(p.include_noise);
  EXPECT_EQ(p.noise_deviation, 0.5);
}

}  // namespace
}  // namespace orcs::aseries
