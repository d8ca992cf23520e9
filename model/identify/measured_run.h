// The measured side of the gap workflow (docs/gap_measured_data.md): one run of the real (or a synthetic)
// robot — the inputs it was commanded and the joint angles it reached, one row per control step.
//
// The native input is the CSV log orcs-sim writes (docs/formats.md, "CSV logs"): '#' comment lines, one of
// them "# columns: time,/Sim/<agent>/<motor>/DesiredAngle,...", then numeric rows whose first column is the
// time in seconds (row 0 = t 0 = the state after reset). Other CSVs are read through a column mapping (JSON)
// that names the time column and, per motor, the columns of its inputs and angle, with scale and offset.
//
// Every problem with the input is an InputError naming the file, the line and/or the column.
#pragma once

#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "model/control/keyframe_record.h"

namespace orcs::identify {

/// When a row's commands act, as the log was recorded.
enum class CommandTiming {
  kUntilRow,  ///< row k's commands acted until row k's time: they produced its state (orcs's logs, the original's)
  kFromRow,   ///< row k's commands were sent after its state was read and act from t(k) to t(k+1) (BAM's logs)
};

/// One run of the real (or synthetic) robot: commanded inputs and measured joint angles, per step.
struct MeasuredRun {
  std::string source;                  ///< the file it was read from, for messages
  std::string agent;                   ///< agent name, from the column paths (or the mapping)
  std::vector<std::string> motors;     ///< motors with a JointAngle column, in column order (e.g. "Right/Knee")
  std::vector<std::string> commanded;  ///< motors with DesiredAngle AND DesiredTorque columns, in column order
  double step = 0.0;                   ///< s, the (uniform) time step of the rows: (last − first time) / (rows − 1)
  std::vector<double> time;            ///< s, per row, starting at 0
  /// per motor name: values per row (same length as time). The inputs are in orcs's timing whatever the file's (a
  /// mapping's "command_timing"): row k's commands, like its supply voltage, act from t(k−1) to t(k).
  std::map<std::string, std::vector<double>> desired_angle;   ///< degrees
  std::map<std::string, std::vector<double>> desired_torque;  ///< raw −1…1
  std::map<std::string, std::vector<double>> joint_angle;     ///< degrees
  std::vector<int> lines;  ///< 1-based line of the source file per row (same length as time), for messages
  /// The file's timing of the inputs; they are already moved to orcs's, so this only says which line each came
  /// from: row k's from row k's line (kUntilRow) or from row k−1's (kFromRow).
  CommandTiming command_timing = CommandTiming::kUntilRow;
  /// The servo's firmware P gain during the run (/Servo/FirmwareKp, register units), per row, when the data has
  /// it (empty otherwise); ParseMeasuredRun checks it is one value throughout. An input of the run for the
  /// physical servo model (docs/model.md, "The physical servo"), never a fitted parameter.
  std::vector<double> firmware_kp;
  std::string firmware_kp_column;  ///< where it came from ("/Servo/FirmwareKp", a mapped column or header key)
  /// The servo's winding temperature (/Servo/WindingTemperature, °C), per row, when the data has it (empty
  /// otherwise); the replay takes the run's mean. An input of the run, like the firmware gain.
  std::vector<double> winding_temperature;
  std::string winding_temperature_column;  ///< where it came from, as firmware_kp_column
  /// The servo's supply voltage (/Servo/SupplyVoltage, V), per row, when the data has it (empty otherwise): the
  /// replay sets each row's voltage for the step that follows it, since a battery or a bench supply sags while the
  /// motor draws current. An input of the run, like the firmware gain.
  std::vector<double> supply_voltage;
  std::string supply_voltage_column;  ///< where it came from, as firmware_kp_column
  /// Accelerometer channels ("ABSR/AccelAxis1": board, then axis) with a column, in column order: the ADXL213
  /// boards' readings, compared with the simulated ones beside the joint angles (docs/gap_measured_data.md,
  /// "Accelerometers").
  std::vector<std::string> accelerometers;
  std::map<std::string, std::vector<double>> acceleration;  ///< per channel: m/s² per row
  /// per channel: the noise of its readings, m/s² (σ), when the mapping gives it; otherwise the model's
  /// /Sim/<agent>/<board>/AccelSensor/Deviation is taken
  std::map<std::string, double> acceleration_noise;
};

/// The run's firmware gain, or nullopt when the data has none.
std::optional<double> FirmwareGain(const MeasuredRun& run);
/// The run's mean winding temperature (°C), or nullopt when the data has none.
std::optional<double> WindingTemperature(const MeasuredRun& run);

/// Where one quantity's values come from in a CSV that is not an orcs log: value = raw · scale + offset, where
/// raw is the number in `column`; or `constant` for every row (then `column` is empty).
struct ColumnSource {
  std::string column;               ///< the header name of the column ("" when constant is set)
  double scale = 1.0;               ///< factor from the file's unit to the quantity's unit (e.g. 0.001 for ms → s)
  double offset = 0.0;              ///< added after scaling, in the quantity's unit
  std::optional<double> constant;   ///< the value of every row instead of a column, in the quantity's unit
  /// A key of the file's comment lines instead of a column: "firmware_kp" reads 400 from "# ... firmware_kp=400"
  /// (only for the servo's inputs firmware_kp, winding_temperature and supply_voltage; then `column` is empty)
  std::string header;
};

/// One motor of a mapped CSV: which columns hold its inputs and its measured angle.
struct ChannelMapping {
  std::string motor;                           ///< motor name as in the rig ("Right/Knee", "Motor")
  std::optional<ColumnSource> desired_angle;   ///< degrees; given together with desired_torque or not at all
  std::optional<ColumnSource> desired_torque;  ///< raw −1…1; given together with desired_angle or not at all
  std::optional<ColumnSource> joint_angle;     ///< degrees, the measured angle; always a column
};

/// One accelerometer axis of a mapped CSV.
struct AccelerometerMapping {
  std::string channel;           ///< "ABSR/AccelAxis1": the board's name, then AccelAxis1 or AccelAxis2
  ColumnSource value;            ///< m/s² after scaling (scale e.g. 9.81 for g); always a column
  std::optional<double> noise;   ///< σ of its readings, m/s²; unset = the model's AccelSensor/Deviation
};

/// Column mapping for CSVs that are not orcs logs (docs/gap_measured_data.md, "Column mapping"), read from JSON.
struct ColumnMapping {
  std::string agent;                     ///< the agent the runs belong to
  ColumnSource time;                     ///< time column, seconds after scaling (scale e.g. 0.001 for ms)
  std::vector<ChannelMapping> channels;  ///< one per motor, in the order they become MeasuredRun::motors
  char delimiter = ',';                  ///< field separator of the CSV (',', ';', '\t', ...)
  std::optional<ColumnSource> firmware_kp;  ///< the servo's firmware P gain: a column, a header key or a constant
  std::optional<ColumnSource> winding_temperature;  ///< °C, the servo's temperature: as firmware_kp
  std::optional<ColumnSource> supply_voltage;  ///< V, the servo's supply voltage per row: as firmware_kp
  CommandTiming command_timing = CommandTiming::kUntilRow;  ///< when a row's commands (and supply voltage) act
  std::vector<AccelerometerMapping> accelerometers;  ///< accelerometer axes to compare, in this order
  std::string source;                    ///< the mapping file, for messages
};

/// Reads and checks a column mapping file (JSON). Throws InputError naming the file and the field.
ColumnMapping ReadColumnMapping(const std::string& path);
/// Checks a parsed mapping: unknown keys, missing "agent"/"time"/"channels", wrong types, a channel with only
/// one of desired_angle/desired_torque, no channel with a joint_angle. Errors read
/// "source: field 'channels[0].joint_angle.column' expected ..., found ...".
ColumnMapping ParseColumnMapping(const nlohmann::json& j, const std::string& source);

/// Parses a run from CSV text. Without a mapping the text is an orcs log whose "# columns:" comment names the
/// columns; with one, the first non-comment line is the header of column names. Throws InputError.
MeasuredRun ParseMeasuredRun(std::string_view text, const std::string& source,
                             const ColumnMapping* mapping = nullptr);
/// Reads and parses a run file; an unreadable file is an InputError naming it.
MeasuredRun ReadMeasuredRun(const std::string& path, const ColumnMapping* mapping = nullptr);

/// Checks that a set of runs can be compared with one rig: same agent, same time step (within 1e-9 s).
/// `role` is "measured" or "holdout" for messages. Throws InputError naming the two files that disagree.
void CheckRunsAgree(const std::vector<MeasuredRun>& runs, const std::string& role = "measured");
/// Throws InputError when a holdout run is also a fit run: the same path (after canonicalisation via
/// std::filesystem::weakly_canonical) or identical contents — message names both files.
void CheckDisjoint(const std::vector<std::string>& fit_paths, const std::vector<std::string>& holdout_paths);

/// The commanded inputs as a keyframe record (model/control/keyframe_record.h, raw layout) for motors
/// `motor_order` (the rig's motors in input order): keyframe i−1 carries row i's inputs (i ≥ 1) and takes
/// effect at max(0, t(i−1) − step/2) · 1000 ms — half a step early so rounding of the simulation's clock never
/// delays it. Each keyframe's line is the line its inputs were read from: row i's, or row i−1's when the file's
/// commands act from their row (CommandTiming::kFromRow). Throws InputError
/// "file: no column '/Sim/<agent>/<motor>/DesiredAngle'" when a motor in motor_order lacks commands.
control::KeyframeRecord CommandsAsRecord(const MeasuredRun& run, const std::vector<std::string>& motor_order);

/// The orcs log column of an accelerometer channel: AccelerometerColumn("Humanoid", "ABSR/AccelAxis1") is
/// "/Sim/Humanoid/ABSR/AccelAxis1".
std::string AccelerometerColumn(const std::string& agent, const std::string& channel);

/// The orcs log column of one motor quantity: MotorColumn("Humanoid", "Right/Knee", "JointAngle") is
/// "/Sim/Humanoid/Right/Knee/JointAngle".
std::string MotorColumn(const std::string& agent, const std::string& motor, const std::string& quantity);

}  // namespace orcs::identify
