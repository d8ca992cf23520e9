// BAM's recorded servo logs (Rhoban's Better Actuator Models), read as measured runs (docs/gap_measured_data.md,
// "BAM's JSON logs").
//
// BAM's recorder writes one JSON object per run: the rig (`mass` kg, `length` m, `kp` firmware gain, `vin` V,
// `motor`, `trajectory`, `dt` s) and `entries`, one object per control step with `timestamp` s, `position` rad,
// `speed` rad/s, `load`, `input_volts` V, `temp` °C, `goal_position` rad and `torque_enable` (bool). orcs reads
// such a log as the table the XL330 CSVs of scenarios/data are (the same logs converted to degrees): a comment
// line with the rig's constants, then the columns time_s, goal_deg, position_deg, speed_deg_s, load,
// input_volts, temperature_c and torque_enable. A column mapping written for those CSVs therefore reads a BAM log
// unchanged, and without one a BAM log is read through BamLogMapping().
#pragma once

#include <string>
#include <string_view>

#include "model/identify/measured_run.h"

namespace orcs::identify {

/// True when `text` is a JSON object (its first character that is not white space is '{'): a BAM log, since
/// a CSV log never starts so.
bool IsBamLog(std::string_view text);

/// BAM's log as the table of the XL330 CSVs (above): "# BAM log: motor=… load_mass_kg=… load_distance_m=…
/// firmware_kp=… supply_v=… dt_s=… trajectory=…" (the keys the log has), the header line and one row per entry.
/// Times count from the first entry's timestamp; angles and speeds are turned into degrees and written with 12
/// significant digits, so that a log converted from degrees comes back to the same degrees. Keys orcs does not
/// read (other rig constants, other entry fields) are ignored, as in a CSV's unread columns. Throws InputError
/// "source: field 'entries[3].position' expected a finite number, found …" for a field missing or of a wrong type.
std::string BamLogAsTable(std::string_view json_text, const std::string& source);

/// The mapping a BAM log is read with when none is given: one pendulum servo (agent "Pendulum", motor "Motor",
/// as scenarios/gap/xl330/), goal and position in degrees as logged, the torque enable as the torque, the
/// firmware gain from the log's `kp` (where the table's comment has it), each entry's supply voltage, and BAM's
/// command timing (it reads the state, then sends the goal: "from_row"). `table` is BamLogAsTable's.
ColumnMapping BamLogMapping(std::string_view table, const std::string& source);

}  // namespace orcs::identify
