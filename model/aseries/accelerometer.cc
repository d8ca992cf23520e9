#include "model/aseries/accelerometer.h"

#include <algorithm>
#include <cmath>

#include "base/demand.h"
#include "model/core/random_stream.h"

namespace orcs::aseries {

AccelerometerBoard MakeAccelerometerBoard(const Eigen::Vector3d& local_position,
                                          const Eigen::Quaterniond& local_rotation) {
  const Eigen::Quaterniond rotation = local_rotation.normalized();
  AccelerometerBoard board;
  board.local_position = local_position;
  board.axes = {rotation * Eigen::Vector3d::UnitZ(), rotation * Eigen::Vector3d::UnitX()};
  return board;
}

void Reset(AccelerometerState& state, const AccelerometerBoard& board, const Eigen::Vector3d& host_position,
           const Eigen::Quaterniond& host_rotation) {
  state.previous_position = host_position + host_rotation * board.local_position;
  state.previous_velocity.setZero();
  state.has_previous_position = true;
  state.last_valid = {0.0, 0.0};
  for (std::array<double, 2>& pair : state.window) pair = {0.0, 0.0};
  state.window_next = 0;
  state.window_count = 0;
}

std::array<double, 2> Measure(const AccelerometerParameters& parameters, const AccelerometerBoard& board,
                              AccelerometerState& state, const Eigen::Vector3d& host_position,
                              const Eigen::Quaterniond& host_rotation, double dt, RandomStream* noise) {
  ORCS_DEMAND(dt > 0.0);
  constexpr int kCapacity = AccelerometerParameters::kMaxWindow;

  // 1. The sensor point in the world.
  const Eigen::Vector3d position = host_position + host_rotation * board.local_position;
  if (!state.has_previous_position) {
    state.previous_position = position;
    state.has_previous_position = true;
  }

  // 2. Finite differences.
  const Eigen::Vector3d velocity = (position - state.previous_position) / dt;
  Eigen::Vector3d acceleration = (velocity - state.previous_velocity) / dt;
  state.previous_position = position;
  state.previous_velocity = velocity;

  // 3. What an accelerometer feels: the acceleration minus gravity (gravity is −g along y).
  acceleration.y() += parameters.gravity;

  // 4. Project on the sensing axes, turned by the host body.
  std::array<double, 2> reading{};
  for (int i = 0; i < 2; ++i) reading[i] = -acceleration.dot(host_rotation * board.axes[i]);

  // 5. Cut-off with hold of both axes.
  if (std::abs(reading[0]) > parameters.cut_off || std::abs(reading[1]) > parameters.cut_off) {
    reading = state.last_valid;
  } else {
    state.last_valid = reading;
  }

  // 6. Moving average over the last N pairs, or over the pairs there are while the window fills.
  state.window[state.window_next] = reading;
  state.window_next = (state.window_next + 1) % kCapacity;
  const int window_size = std::clamp(parameters.low_pass_filter_delay, 1, kCapacity);
  state.window_count = std::min(state.window_count + 1, window_size);
  std::array<double, 2> output{0.0, 0.0};
  for (int k = state.window_count; k >= 1; --k) {  // oldest to newest
    const std::array<double, 2>& pair = state.window[(state.window_next - k + kCapacity) % kCapacity];
    output[0] += pair[0];
    output[1] += pair[1];
  }
  for (double& value : output) value /= state.window_count;

  // 7. Noise, then the output range.
  const bool noisy = parameters.deviation > 0.0 && noise != nullptr;
  for (double& value : output) {
    if (noisy) value += noise->Normal(0.0, parameters.deviation);
    value = std::clamp(value, -parameters.range, parameters.range);
  }
  return output;
}

}  // namespace orcs::aseries
