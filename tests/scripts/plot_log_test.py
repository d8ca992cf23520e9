"""scripts/plot_log.py on small logs written here in the format orcs-sim and orcs-batch write (docs/formats.md,
"CSV logs"): as a program — the PNG is written, bad input is exit 2 with one line naming the file and line, an
unknown channel lists the close names — and as a module, whose figure is inspected: one panel per channel, titles,
units in the y labels, a legend naming every run below the panels.

Run: cd tests/scripts && /usr/bin/python3 -m unittest -v plot_log_test
"""

import math
import os
import sys
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from script_helpers import (HAVE_MATPLOTLIB, NO_MATPLOTLIB, TempDirTest, call_main, is_png, legend_texts,  # noqa: E402
                            legends_covering_axes, load_script, run_script)

KNEE = "/Sim/Humanoid/Right/Knee/JointAngle"
KNEE_DESIRED = "/Sim/Humanoid/Right/Knee/DesiredAngle"
TORQUE = "/Sim/Humanoid/Right/Knee/MotorTorque"
HEAD = "/Sim/Humanoid/Middle/Head/Position"
COLUMNS = ["time", f"{HEAD}.x", f"{HEAD}.y", f"{HEAD}.z", KNEE_DESIRED, KNEE, TORQUE]


def log_text(amplitude=20.0, steps=50, header=("orcs job log", "scenario: stand-network", "seed: 1"),
             columns=COLUMNS, extra_rows="", truncated_at=None):
    """A log as orcs-batch writes it: comments, '# columns:', one row per 10 ms step."""
    lines = [f"# {h}" for h in header] + ["# columns: " + ",".join(columns)]
    for k in range(steps):
        t = k * 0.01
        angle = amplitude * math.sin(2 * math.pi * t)
        values = [t, 0.001, 0.4 - 0.01 * t, 0.05, amplitude, angle, 0.1 * angle / max(amplitude, 1)]
        lines.append(",".join(repr(v) for v in values[: len(columns)]))
    if truncated_at is not None:
        lines.append(f"# log truncated at time {truncated_at} s: it reached its bound of 1000 bytes")
    return "\n".join(lines) + "\n" + extra_rows


@unittest.skipUnless(HAVE_MATPLOTLIB, NO_MATPLOTLIB)
class PlotLogTest(TempDirTest):
    def setUp(self):
        super().setUp()
        self.module = load_script("plot_log")

    def batch(self, name, jobs=("job-0",), sets=1, amplitude=20.0):
        """An orcs-batch output folder NAME with DIR/logs/JOB.csv (or JOB.set-K.csv)."""
        for job in jobs:
            for k in range(sets):
                file = f"{job}.csv" if sets == 1 else f"{job}.set-{k}.csv"
                self.write(f"{name}/logs/{file}", log_text(amplitude + 5 * k))
        self.write(f"{name}/results.jsonl", "{}\n")
        return os.path.join(self.dir, name)

    def figure(self, runs, patterns, job=None, parameter_set=None, by="channel"):
        """The figure plot_log.py would draw, built by its own functions."""
        lines = self.module.gather(runs, job, parameter_set)
        channels = self.module.select_channels([line["log"] for line in lines], patterns)
        for line in lines:
            line["log"].load(channels)
        return self.module.build_figure(lines, channels, patterns, by, job=job)

    # --- as a program -------------------------------------------------------------------------------------------

    def test_two_runs_make_a_png_and_name_it(self):
        ode, mujoco = self.batch("ode"), self.batch("mujoco", amplitude=25)
        out = os.path.join(self.dir, "knee.png")
        run = run_script("plot_log", ode, mujoco, "--channel", "Knee/JointAngle", "--out", out)
        self.assertEqual(run.returncode, 0, run.stderr)
        self.assertTrue(is_png(out))
        self.assertGreater(os.path.getsize(out), 5000)
        self.assertIn(f"wrote {out}", run.stdout)
        self.assertEqual([f for f in os.listdir(self.dir) if ".tmp" in f], [], "no temporary file left")

    def test_a_single_csv_file_is_a_run(self):
        path = self.write("sim.csv", log_text(header=("orcs-sim log", "environment: scenarios/environments/x.xml")))
        out = os.path.join(self.dir, "sim.png")
        code, _, err = call_main(self.module, path, "--channel", "Knee", "--out", out)
        self.assertEqual(code, 0, err)
        self.assertTrue(is_png(out))
        figure = self.figure([path], ["Knee/JointAngle"])
        self.assertEqual(figure._suptitle.get_text(), "x: Knee/JointAngle", "the environment names an orcs-sim log")
        self.assertEqual(legend_texts(figure), ["sim"])

    def test_a_folder_with_several_jobs_needs_job_and_lists_them(self):
        folder = self.batch("many", jobs=("job-0", "job-1", "job-2"))
        run = run_script("plot_log", folder, "--channel", "Knee", "--out", os.path.join(self.dir, "x.png"))
        self.assertEqual(run.returncode, 2)
        self.assertIn(os.path.join(folder, "logs"), run.stderr)
        self.assertIn("job-0, job-1, job-2", run.stderr)
        self.assertIn("--job", run.stderr)
        self.assertEqual(run.stderr.count("\n"), 1, run.stderr)
        code, _, err = call_main(self.module, folder, "--job", "job-7", "--channel", "Knee")
        self.assertEqual(code, 2)
        self.assertIn("no log of job 'job-7'", err)
        self.assertIn("job-0", err)
        out = os.path.join(self.dir, "job1.png")
        code, _, err = call_main(self.module, folder, "--job", "job-1", "--channel", "Knee", "--out", out)
        self.assertEqual(code, 0, err)
        self.assertTrue(is_png(out))
        self.assertIn("job-1", self.figure([folder], ["Knee"], job="job-1")._suptitle.get_text())

    def test_an_unknown_channel_is_exit_2_listing_close_names(self):
        folder = self.batch("a")
        run = run_script("plot_log", folder, "--channel", "Knee/JointAngel", "--out", os.path.join(self.dir, "x.png"))
        self.assertEqual(run.returncode, 2)
        self.assertIn("--channel 'Knee/JointAngel'", run.stderr)
        self.assertIn(os.path.join(folder, "logs", "job-0.csv"), run.stderr)
        self.assertIn(f"close: {KNEE}", run.stderr)
        self.assertEqual(run.stderr.count("\n"), 1, run.stderr)
        self.assertFalse(os.path.exists(os.path.join(self.dir, "x.png")))
        # Nothing close: the log's columns are listed instead.
        code, _, err = call_main(self.module, folder, "--channel", "Accelerometer")
        self.assertEqual(code, 2)
        self.assertIn(f"the log has {HEAD}.x", err)
        code, _, err = call_main(self.module, folder, "--channel", "(")
        self.assertEqual(code, 2)
        self.assertIn("not a regular expression", err)

    def test_bad_logs_are_exit_2_naming_the_file_and_line(self):
        bad_cell = self.write("bad_cell.csv", log_text(extra_rows="0.5,0,0.4,0.05,20,abc,0\n"))
        bad_count = self.write("bad_count.csv", log_text(extra_rows="0.5,0,0.4\n"))
        no_columns = self.write("no_columns.csv", "0,1,2\n0.01,1,2\n")
        no_rows = self.write("no_rows.csv", log_text(steps=0))
        not_time = self.write("not_time.csv", log_text(columns=["t"] + COLUMNS[1:]))
        cases = [
            (bad_cell, f"{bad_cell}:55: column {KNEE}: expected a number, found 'abc'"),
            (bad_count, f"{bad_count}:55: expected 7 fields"),
            (no_columns, f"{no_columns}:1: a data row before the '# columns:' comment"),
            (no_rows, f"{no_rows}: no data rows"),
            (not_time, f"{not_time}:4: the first column must be 'time'"),
            (os.path.join(self.dir, "missing.csv"), f"{os.path.join(self.dir, 'missing.csv')}: no such file"),
            (os.path.join(self.dir, "empty_dir"), "no CSV logs"),
        ]
        os.makedirs(os.path.join(self.dir, "empty_dir"))
        for path, message in cases:
            with self.subTest(path=os.path.basename(path)):
                code, _, err = call_main(self.module, path, "--channel", "Knee", "--out",
                                         os.path.join(self.dir, "x.png"))
                self.assertEqual(code, 2, err)
                self.assertIn(message, err)
                self.assertTrue(err.startswith("plot_log.py: "), err)
                self.assertEqual(err.count("\n"), 1, err)
        self.assertFalse(os.path.exists(os.path.join(self.dir, "x.png")))
        # As a program too: one line, no traceback.
        run = run_script("plot_log", bad_cell, "--channel", "Knee", "--out", os.path.join(self.dir, "x.png"))
        self.assertEqual(run.returncode, 2)
        self.assertEqual(run.stderr, f"plot_log.py: {bad_cell}:55: column {KNEE}: expected a number, found 'abc'\n")

    def test_a_text_column_is_left_out_with_a_note(self):
        columns = ["time", "/Sim/Floor/Material", KNEE]
        text = "# orcs-sim log\n# columns: " + ",".join(columns) + "\n" + "".join(
            f"{k * 0.01},PVC,{k}\n" for k in range(5))
        path = self.write("material.csv", text)
        out = os.path.join(self.dir, "m.png")
        code, _, err = call_main(self.module, path, "--channel", "Material|JointAngle", "--out", out)
        self.assertEqual(code, 0, err)
        self.assertIn("column /Sim/Floor/Material holds text", err)
        code, _, err = call_main(self.module, path, "--channel", "Material", "--out", out)
        self.assertEqual(code, 2)
        self.assertIn("hold text, not numbers", err)

    # --- the figure ---------------------------------------------------------------------------------------------

    def test_one_panel_per_channel_with_units_titles_and_a_legend_naming_the_runs(self):
        ode, mujoco = self.batch("ode"), self.batch("mujoco", amplitude=25)
        figure = self.figure([ode, mujoco], ["Knee/(Joint|Desired)Angle", "MotorTorque", r"Head/Position\.y"])
        axes = figure.axes
        # In the order of the --channel expressions.
        self.assertEqual([a.get_title(loc="left") for a in axes], [KNEE_DESIRED, KNEE, TORQUE, f"{HEAD}.y"])
        self.assertEqual([a.get_ylabel() for a in axes], ["Knee/DesiredAngle (deg)", "Knee/JointAngle (deg)",
                                                           "Knee/MotorTorque (N·m)", "Head/Position.y (m)"])
        self.assertEqual(axes[-1].get_xlabel(), "simulated time (s)")
        for axis in axes:
            self.assertEqual(len(axis.get_lines()), 2, axis.get_title(loc="left"))
        title = figure._suptitle.get_text()
        self.assertIn("stand-network", title)
        self.assertIn("job-0", title)
        self.assertIn("4 channels matching", title)
        self.assertEqual(legend_texts(figure), ["ode", "mujoco"])
        self.assertEqual(legends_covering_axes(figure), [])
        # The lines are the logged values against the logged time.
        line = axes[1].get_lines()[1]
        self.assertAlmostEqual(max(line.get_ydata()), 25.0, delta=0.1)
        self.assertAlmostEqual(line.get_xdata()[-1], 0.49)

    def test_few_channels_are_named_in_the_title(self):
        figure = self.figure([self.batch("a")], ["Knee/JointAngle"])
        self.assertEqual(figure._suptitle.get_text(), "stand-network, job-0: Knee/JointAngle")

    def test_each_parameter_set_is_a_line_and_set_picks_one(self):
        folder = self.batch("sets", sets=3)
        figure = self.figure([folder], ["Knee/JointAngle"], job="job-0")
        self.assertEqual(legend_texts(figure), ["sets, set 0", "sets, set 1", "sets, set 2"])
        colours = {line.get_color() for line in figure.axes[0].get_lines()}
        self.assertEqual(len(colours), 3, "one run: a colour per set")
        figure = self.figure([folder], ["Knee/JointAngle"], job="job-0", parameter_set=2)
        self.assertEqual(legend_texts(figure), ["sets"])
        self.assertAlmostEqual(max(figure.axes[0].get_lines()[0].get_ydata()), 30.0, delta=0.1)
        with self.assertRaisesRegex(self.module.InputProblem, "no log of parameter set 5"):
            self.module.gather([folder], "job-0", 5)

    def test_a_log_file_of_a_batch_names_its_job_and_set(self):
        folder = self.batch("sets", sets=2)
        figure = self.figure([os.path.join(folder, "logs", "job-0.set-1.csv")], ["Knee/JointAngle"])
        self.assertEqual(figure._suptitle.get_text(), "stand-network, job-0: Knee/JointAngle")
        self.assertEqual(legend_texts(figure), ["job-0.set-1"])

    def test_an_evolve_folder_shows_the_winner_unless_job_names_another(self):
        for job in ("winner", "validate-1", "validate-2"):
            self.write(f"evolve/best/logs/{job}.set-0.csv", log_text(amplitude=30 if job == "winner" else 10))
        folder = os.path.join(self.dir, "evolve")
        figure = self.figure([folder], ["Knee/JointAngle"])
        self.assertIn("winner", figure._suptitle.get_text())
        self.assertAlmostEqual(max(figure.axes[0].get_lines()[0].get_ydata()), 30.0, delta=0.1)
        figure = self.figure([folder], ["Knee/JointAngle"], job="validate-2")
        self.assertIn("validate-2", figure._suptitle.get_text())

    def test_runs_with_the_same_name_are_told_apart_by_their_path(self):
        first = self.batch("one/run")
        second = self.batch("two/run")
        figure = self.figure([first, second], ["Knee/JointAngle"])
        self.assertEqual(legend_texts(figure), [os.path.normpath(first), os.path.normpath(second)])

    def test_by_unit_puts_channels_of_one_unit_in_one_panel(self):
        figure = self.figure([self.batch("a")], ["Knee/(Joint|Desired)Angle", "MotorTorque"], by="unit")
        self.assertEqual(len(figure.axes), 2)
        self.assertEqual([a.get_ylabel() for a in figure.axes], ["deg", "Knee/MotorTorque (N·m)"])
        self.assertEqual(len(figure.axes[0].get_lines()), 2)
        self.assertIn("Knee/JointAngle, a", legend_texts(figure))
        self.assertEqual(legends_covering_axes(figure), [])

    def test_a_truncated_log_says_so_in_the_legend(self):
        path = self.write("cut.csv", log_text(truncated_at="0.49"))
        out = os.path.join(self.dir, "cut.png")
        code, _, err = call_main(self.module, path, "--channel", "Knee/JointAngle", "--out", out)
        self.assertEqual(code, 0, err)
        self.assertEqual(legend_texts(self.figure([path], ["Knee/JointAngle"])), ["cut (log truncated at 0.49 s)"])

    def test_too_many_panels_are_refused(self):
        columns = ["time"] + [f"/Sim/A/M{k}/JointAngle" for k in range(14)]
        text = "# columns: " + ",".join(columns) + "\n" + "0," + ",".join("1" * 14) + "\n"
        path = self.write("wide.csv", text)
        code, _, err = call_main(self.module, path, "--channel", "JointAngle")
        self.assertEqual(code, 2)
        self.assertIn("14 panels", err)
        self.assertIn("--by unit", err)
        code, _, err = call_main(self.module, path, "--channel", "JointAngle", "--by", "unit", "--out",
                                 os.path.join(self.dir, "wide.png"))
        self.assertEqual(code, 0, err)


if __name__ == "__main__":
    unittest.main()
