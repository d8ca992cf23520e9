// Where a servo model keeps what the bus driver reads and writes: the control-table addresses and sizes of the
// A-Series' AX-12+ (Protocol 1.0) and of the XL330 (Protocol 2.0), with how a position register maps to degrees.
// From the ROBOTIS e-Manuals' control tables; the servo-bus emulator answers with the same layout.
#pragma once

#include <cstdint>
#include <string_view>

namespace orcs::dynamixel {

/// The Dynamixel protocol a bus speaks.
enum class Protocol : std::uint8_t {
  kV1 = 1,  ///< Protocol 1.0: AX-12+, AX-18, RX, MX (1.0 firmware)
  kV2 = 2,  ///< Protocol 2.0: XL330, XL430, XM/XH, MX (2.0 firmware)
};

/// One servo model's control table, as far as orcs uses it.
struct ControlTable {
  std::string_view name;                 ///< "AX-12+", "XL330-M288"
  Protocol protocol = Protocol::kV1;     ///< what it speaks
  std::uint16_t model_number = 0;        ///< answered by PING (2.0) and at address 0
  std::uint16_t torque_enable = 0;       ///< address of Torque Enable (1 byte; 1 = holding)
  std::uint16_t goal_position = 0;       ///< address of Goal Position
  std::uint16_t present_position = 0;    ///< address of Present Position
  std::uint16_t present_speed = 0;       ///< address of Present Speed / Velocity
  std::uint16_t present_load = 0;        ///< address of Present Load / PWM (what the log's `load` is)
  std::uint16_t present_voltage = 0;     ///< address of Present (Input) Voltage
  std::uint16_t present_temperature = 0; ///< address of Present Temperature (1 byte, °C)
  std::uint8_t position_size = 2;        ///< bytes of a position register (2 in 1.0, 4 in 2.0)
  std::uint8_t speed_size = 2;           ///< bytes of the speed register
  std::uint8_t load_size = 2;            ///< bytes of the load register
  std::uint8_t voltage_size = 1;         ///< bytes of the voltage register
  double voltage_unit = 0.1;             ///< V per unit of the voltage register
  double degrees_per_tick = 0.0;         ///< position resolution, degrees per tick
  std::int32_t center_tick = 0;          ///< the tick of 0° (the middle of the range)
  std::int32_t max_tick = 0;             ///< the highest position tick (the lowest is 0)
  double speed_unit = 0.0;               ///< degrees per second per unit of the speed register
  std::uint16_t table_size = 0;          ///< bytes of the whole table (the emulator's memory)
  std::uint16_t torque_limit = 0;        ///< address of the torque limit in RAM, 2 bytes (AX-12: Torque Limit; XL330: Goal PWM)
  std::uint16_t torque_limit_full = 0;   ///< its value for 100 % (AX-12: 1023; XL330: 885)
};

/// The AX-12+: 0…1023 over 300°, 512 = 0°; speed in 0.111 rpm with bit 10 the direction.
inline constexpr ControlTable kAx12{.name = "AX-12+", .protocol = Protocol::kV1, .model_number = 12,
                                     .torque_enable = 24, .goal_position = 30, .present_position = 36,
                                     .present_speed = 38, .present_load = 40, .present_voltage = 42,
                                     .present_temperature = 43, .position_size = 2, .speed_size = 2,
                                     .load_size = 2, .voltage_size = 1, .voltage_unit = 0.1,
                                     .degrees_per_tick = 300.0 / 1024.0, .center_tick = 512, .max_tick = 1023,
                                     .speed_unit = 0.111 * 6.0, .table_size = 50, .torque_limit = 34,
                                     .torque_limit_full = 1023};

/// The XL330-M288: 0…4095 per turn, 2048 = 0°; velocity in 0.229 rpm, signed; Present PWM as the load.
inline constexpr ControlTable kXl330{.name = "XL330-M288", .protocol = Protocol::kV2, .model_number = 1200,
                                      .torque_enable = 64, .goal_position = 116, .present_position = 132,
                                      .present_speed = 128, .present_load = 124, .present_voltage = 144,
                                      .present_temperature = 146, .position_size = 4, .speed_size = 4,
                                      .load_size = 2, .voltage_size = 2, .voltage_unit = 0.1,
                                      .degrees_per_tick = 360.0 / 4096.0, .center_tick = 2048, .max_tick = 4095,
                                      .speed_unit = 0.229 * 6.0, .table_size = 148, .torque_limit = 100,
                                      .torque_limit_full = 885};

}  // namespace orcs::dynamixel
