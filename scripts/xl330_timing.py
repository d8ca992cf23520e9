#!/usr/bin/env python3
"""When does a row's goal act in the XL330 pendulum logs? (docs/gap.md, "A real servo")

The servo's firmware computes its PWM duty from the goal it holds and the position it reads: with only a P gain,
present PWM = P / 256 × (goal − position) in encoder pulses (0.088°), up to its 885 limit. The logs' "load" column
is that present PWM, read with the row's position. Comparing it with the goal of the row before, the row itself
and the row after tells which goal the firmware held at the row's reading: the row's own means the logger read
the state and then sent the goal (a mapping's "command_timing": "from_row"); the next row's would mean the row's
goal had already acted before its reading ("until_row", orcs's own logs).

    scripts/xl330_timing.py [DATA_DIR]

DATA_DIR defaults to scenarios/data/xl330-pendulum. Prints, per firmware gain, the RMS difference (PWM units)
between the load column and P/256 × (goal of row k + shift − position of row k) over the rows with the torque on
and neither value near the PWM limit.
"""
import csv
import math
import pathlib
import sys

PULSE_DEG = 360.0 / 4096.0  # one encoder pulse
PWM_LIMIT = 885.0           # the XL330's PWM Limit register's factory value
UNSATURATED = 800.0         # rows with |PWM| above this may be clipped and are left out
TRAJECTORIES = ("sin_sin", "lift_and_drop", "up_and_down", "sin_time_square")
SHIFTS = {-1: "row k−1's goal", 0: "row k's goal (from_row)", 1: "row k+1's goal (until_row)"}


def read_log(path):
    lines = [line for line in path.read_text().splitlines() if line and not line.startswith("#")]
    rows = list(csv.DictReader(lines))
    if not rows:
        sys.exit(f"xl330_timing.py: {path}: no rows")
    column = lambda name: [float(row[name]) for row in rows]
    try:
        load = [value - 65536.0 if value > 32767.0 else value for value in column("load")]  # unsigned 16-bit read
        return column("goal_deg"), column("position_deg"), load, column("torque_enable")
    except KeyError as missing:
        sys.exit(f"xl330_timing.py: {path}: no column {missing}")


def squared_errors(path, gain, shift):
    goal, position, load, torque = read_log(path)
    errors = []
    for k in range(1, len(goal) - 1):
        if torque[k] == 0 or torque[k + shift] == 0:
            continue
        predicted = gain / 256.0 * (goal[k + shift] - position[k]) / PULSE_DEG
        if abs(predicted) < UNSATURATED and abs(load[k]) < UNSATURATED:
            errors.append((predicted - load[k]) ** 2)
    return errors


def main():
    data = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else "scenarios/data/xl330-pendulum")
    print(f"RMS of load − P/256 × (goal − position) / {PULSE_DEG:.4f}°, PWM units (limit {PWM_LIMIT:.0f}):")
    for gain in (100, 400):
        paths = [data / f"{trajectory}_kp{gain}.csv" for trajectory in TRAJECTORIES]
        for path in paths:
            if not path.is_file():
                sys.exit(f"xl330_timing.py: {path}: cannot read")
        for shift, name in SHIFTS.items():
            errors = [e for path in paths for e in squared_errors(path, gain, shift)]
            print(f"  kp{gain}  {name:28s} {math.sqrt(sum(errors) / len(errors)):6.2f}  ({len(errors)} rows)")


if __name__ == "__main__":
    main()
