// The ADXL213 two-axis acceleration board of the A-Series (spec/aseries.md §5): the acceleration of a point
// fixed to a host body, from finite differences of its position, plus gravity, projected on two sensing axes;
// with a cut-off that holds the last in-range pair, a moving average, Gaussian noise and the output range.
// Pure computation: the caller passes the host body's pose after each physics step and stores the result as
// <board>/AccelAxis1 and AccelAxis2. No allocation. Decisions: docs/model.md, "Sensors".
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>

#include "model/aseries/parameter_table.h"

namespace orcs {
class RandomStream;
}

namespace orcs::aseries {

/// One board's parameters (each board has its own copies of the /AccelSensor/... values: per_motor_parameters.h).
struct AccelerometerParameters {
  double deviation = 0.0001;      ///< σ of the reading noise, m/s², 0 = none, /AccelSensor/Deviation
  int low_pass_filter_delay = 1;  ///< moving-average window N, samples, 1..kMaxWindow, /AccelSensor/LowPassFilterDelay
  double gravity = 9.81;          ///< gravity magnitude along −y, m/s², /Simulation/Gravitation
  double cut_off = 11.772;        ///< |reading| above which the last in-range pair is held, m/s² (1.2 g), /AccelSensor/CutOff
  double range = 16.072704;       ///< readings are clamped to ±range, m/s² (±1.6384 g), /AccelSensor/Range

  static constexpr int kMaxWindow = 64;  ///< capacity of the moving-average window
};

/// Repository paths of a board's own AccelerometerParameters fields (copied per board: /Sim/<agent>/<board> + path).
inline constexpr std::array<ParameterField<AccelerometerParameters>, 4> kAccelerometerParameterTable{{
    {"/AccelSensor/Deviation", &AccelerometerParameters::deviation},
    {"/AccelSensor/LowPassFilterDelay", &AccelerometerParameters::low_pass_filter_delay},
    {"/AccelSensor/CutOff", &AccelerometerParameters::cut_off},
    {"/AccelSensor/Range", &AccelerometerParameters::range},
}};

/// The gravity every board adds: the simulation's, one value for all.
inline constexpr std::array<ParameterField<AccelerometerParameters>, 1> kAccelerometerGravityTable{{
    {"/Simulation/Gravitation", &AccelerometerParameters::gravity},
}};

/// Where a board sits on its host body and where it senses: both in the host body's frame.
struct AccelerometerBoard {
  Eigen::Vector3d local_position = Eigen::Vector3d::Zero();  ///< sensor point in the host frame, m
  std::array<Eigen::Vector3d, 2> axes{Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitX()};  ///< unit, host frame
};

/// A board from its placement (spec §5 table): the board-frame axes Axis1 = (0,0,1), Axis2 = (1,0,0) turned by
/// the board's local rotation.
AccelerometerBoard MakeAccelerometerBoard(const Eigen::Vector3d& local_position,
                                          const Eigen::Quaterniond& local_rotation);

/// The memory of one board. Value-initialise it, then Reset it at every simulation reset.
struct AccelerometerState {
  Eigen::Vector3d previous_position = Eigen::Vector3d::Zero();  ///< p_prev, world, m
  Eigen::Vector3d previous_velocity = Eigen::Vector3d::Zero();  ///< v_prev, world, m/s
  /// False until p_prev is known (Reset sets it). A Measure without it takes the current point as p_prev.
  bool has_previous_position = false;
  std::array<double, 2> last_valid{0.0, 0.0};  ///< the last pair within the cut-off, m/s²
  /// The last pairs after the cut-off, a ring: the newest is at (window_next − 1) mod capacity.
  std::array<std::array<double, 2>, AccelerometerParameters::kMaxWindow> window{};
  int window_next = 0;   ///< where the next pair goes
  int window_count = 0;  ///< pairs the average is taken over (≤ N)
};

/// Clears the board's memory at a simulation reset: p_prev = the sensor point for this host pose, v_prev = 0,
/// last valid pair (0, 0), empty window.
void Reset(AccelerometerState& state, const AccelerometerBoard& board, const Eigen::Vector3d& host_position,
           const Eigen::Quaterniond& host_rotation);

/// One reading (spec §5 steps 1–7) for the host body's pose after the physics step of length `dt` > 0:
/// {AccelAxis1, AccelAxis2} in m/s². `noise` draws the reading noise (axis 1, then axis 2); nullptr = none.
std::array<double, 2> Measure(const AccelerometerParameters& parameters, const AccelerometerBoard& board,
                              AccelerometerState& state, const Eigen::Vector3d& host_position,
                              const Eigen::Quaterniond& host_rotation, double dt, RandomStream* noise);

}  // namespace orcs::aseries
