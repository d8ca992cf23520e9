"""scripts/xl330_timing.py: which row's goal the servo's firmware held when a row's PWM was read, checked on
synthetic logs whose PWM column is computed with a known timing.

Run: cd tests/scripts && /usr/bin/python3 -m unittest -v xl330_timing_test
"""

import math
import os
import re
import sys
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from script_helpers import TempDirTest, run_script  # noqa: E402

TRAJECTORIES = ("sin_sin", "lift_and_drop", "up_and_down", "sin_time_square")
PULSE_DEG = 360.0 / 4096.0


def log(gain, goal_shift):
    """A 2 s log whose load column is P/256 × (goal of row k + goal_shift − position of row k), negative PWM as the
    servo's unsigned 16-bit read, the torque off for a while (those rows carry no PWM)."""
    rows = ["# XL330 pendulum log: firmware_kp=%d" % gain,
            "time_s,goal_deg,position_deg,speed_deg_s,load,input_volts,temperature_c,torque_enable"]
    goal = [20.0 * math.sin(0.05 * k) for k in range(401)]
    position = [20.0 * math.sin(0.05 * (k - 3)) for k in range(401)]
    for k in range(400):
        torque = 0 if 150 <= k < 170 else 1
        pwm = round(gain / 256.0 * (goal[k + goal_shift] - position[k]) / PULSE_DEG) if torque else 0
        rows.append(f"{0.005 * k:.3f},{goal[k]},{position[k]},0,{pwm + 65536 if pwm < 0 else pwm},7.4,30,{torque}")
    return "\n".join(rows) + "\n"


class Xl330TimingTest(TempDirTest):
    def write_logs(self, goal_shift):
        for gain in (100, 400):
            for trajectory in TRAJECTORIES:
                self.write(f"logs/{trajectory}_kp{gain}.csv", log(gain, goal_shift))
        return os.path.join(self.dir, "logs")

    def rms_by_timing(self, goal_shift):
        result = run_script("xl330_timing", self.write_logs(goal_shift))
        self.assertEqual(result.returncode, 0, result.stderr)
        found = {}
        for line in result.stdout.splitlines():
            match = re.match(r"\s+kp(\d+)\s+row (k[−+]1|k)'s goal.*?\s([\d.]+)\s+\((\d+) rows\)", line)
            if match:
                found[(int(match.group(1)), match.group(2))] = float(match.group(3))
        self.assertEqual(len(found), 6, result.stdout)
        return found

    def test_the_goal_the_pwm_was_computed_with_fits_to_the_rounding(self):
        for shift, row in ((0, "k"), (1, "k+1")):
            found = self.rms_by_timing(shift)
            for gain in (100, 400):
                self.assertLess(found[(gain, row)], 0.6, found)  # the PWM's rounding to whole units
                others = [value for (g, r), value in found.items() if g == gain and r != row]
                self.assertTrue(all(value > 2.0 for value in others), found)

    def test_a_missing_log_is_one_line_naming_it(self):
        folder = self.write_logs(0)
        os.remove(os.path.join(folder, "up_and_down_kp400.csv"))
        result = run_script("xl330_timing", folder)
        self.assertNotEqual(result.returncode, 0)
        self.assertEqual(result.stderr.strip(), f"xl330_timing.py: {folder}/up_and_down_kp400.csv: cannot read")


if __name__ == "__main__":
    unittest.main()
