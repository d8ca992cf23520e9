"""What a reader needs from the plots of scripts/plot_evolution.py, plot_sweep.py and plot_gap.py, checked on the
figures they build from small inputs written here: titles that name the scenario and what was measured, axis
labels with units, which way fitness is better, integer generation ticks, legends that cover no data, and for
the gap's worst channels a residual panel under each trace whose y-range shows the gap. Each script also runs
once as a program with the command line its callers use (orcs-batch evolve, orcs-batch sweep's hint, orcs-gap's
hint, tests/clients/gap/plot_gap_test.cc), writing its PNGs.

Run: cd tests/scripts && /usr/bin/python3 -m unittest -v plot_quality_test
"""

import json
import math
import os
import sys
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from script_helpers import (HAVE_MATPLOTLIB, NO_MATPLOTLIB, TempDirTest, call_main, is_png, legend_texts,  # noqa: E402
                            legends_covering_axes, load_script, run_script)

FITNESS_HEADER = "generation,evaluations,failed,best,mean,median,worst,best_so_far,seconds\n"
GAP_HEADER = "time,measured,before,refit,after,desired,velocity,speed,acceleration,load,command_error\n"


@unittest.skipUnless(HAVE_MATPLOTLIB, NO_MATPLOTLIB)
class EvolutionPlotTest(TempDirTest):
    def setUp(self):
        super().setUp()
        self.module = load_script("plot_evolution")
        # 12 generations, generation 0 without an ok job (empty fields), as orcs-batch evolve writes them.
        rows = ["0,6,6,,,,,,0.5"]
        best = -5.0
        for g in range(1, 12):
            best = max(best, -4.0 + 0.5 * g)
            rows.append(f"{g},6,0,{-4.0 + 0.5 * g},{-6.0 + 0.4 * g},{-5.5 + 0.4 * g},{-12.0 + 0.2 * g},{best},0.25")
        self.write("run/fitness.csv", FITNESS_HEADER + "\n".join(rows) + "\n")
        self.write("run/checkpoint.json", json.dumps({"format": "orcs evolve checkpoint 1", "fingerprint": {
            "scenario": "rock-oscillator", "algorithm": "cmaes", "population": 6, "seed": 1}}))
        self.folder = os.path.join(self.dir, "run")

    def test_labels_ticks_and_legend(self):
        rows = self.module.read_history(os.path.join(self.folder, "fitness.csv"))
        figure = self.module.build_figure(rows, "a title")
        axis = figure.axes[0]
        self.assertEqual(axis.get_title(), "a title")
        self.assertEqual(axis.get_ylabel(), "fitness (higher is better)")
        self.assertEqual(axis.get_xlabel(), "generation")
        figure.canvas.draw()
        ticks = [t for t in axis.get_xticks() if axis.get_xlim()[0] <= t <= axis.get_xlim()[1]]
        self.assertGreater(len(ticks), 2)
        self.assertTrue(all(float(t).is_integer() for t in ticks), ticks)
        self.assertEqual(legend_texts(figure), ["generation: worst … best", "generation median", "generation best",
                                                "best so far"])
        self.assertEqual(legends_covering_axes(figure), [])

    def test_the_best_so_far_shows_the_last_generations_gain(self):
        # The last generation improves on the one before: its level must be drawn, not a bare rise at the edge.
        rows = self.module.read_history(os.path.join(self.folder, "fitness.csv"))
        figure = self.module.build_figure(rows, "a title")
        figure.canvas.draw()
        line = next(l for l in figure.axes[0].get_lines() if l.get_label() == "best so far")
        vertices = line.get_path().vertices
        last_generation, last_best = rows[-1]["generation"], rows[-1]["best_so_far"]
        self.assertGreater(last_best, rows[-2]["best_so_far"], "the input gains in its last generation")
        level = [(x, y) for x, y in vertices if y == last_best]
        self.assertGreaterEqual(max(x for x, _ in level) - min(x for x, _ in level), 0.5,
                                "the last value holds for half a generation or more")
        self.assertEqual(max(x for x, _ in level), last_generation)

    def test_the_default_title_names_the_scenario_and_algorithm(self):
        self.assertEqual(self.module.default_title(self.folder),
                         "rock-oscillator: fitness per generation (cmaes, 6 genomes per generation)")
        os.remove(os.path.join(self.folder, "checkpoint.json"))
        self.assertEqual(self.module.default_title(self.folder), "run: fitness per generation")
        self.write("run/checkpoint.json", "{not json")
        self.assertEqual(self.module.default_title(self.folder), "run: fitness per generation")

    def test_the_command_orcs_batch_evolve_runs(self):
        run = run_script("plot_evolution", self.folder)
        self.assertEqual(run.returncode, 0, run.stderr)
        self.assertEqual(run.stdout, f"plot_evolution.py: {os.path.join(self.folder, 'fitness.png')}\n")
        self.assertTrue(is_png(os.path.join(self.folder, "fitness.png")))
        self.write("bad/fitness.csv", FITNESS_HEADER + "0,5,0,1,1,1,1,1,0.5\n1,5,0,abc,1,1,1,1,0.5\n")
        code, _, err = call_main(self.module, os.path.join(self.dir, "bad"))
        self.assertEqual(code, 2)
        self.assertIn("fitness.csv:3: column 'best'", err)


def grid_sweep_csv():
    lines = ["/Simulation/ODE/FrictionScaling,/AngularMotor/MaxVelocity,fitness,min_fitness,max_fitness,ok,jobs"]
    for friction in (0.6, 1.0, 1.4):
        for velocity in (2, 4):
            fitness = -5 + friction - 0.2 * velocity
            lines.append(f"{friction},{velocity},{fitness},{fitness - 0.3},{fitness + 0.2},2,2")
    return "\n".join(lines) + "\n"


def lhs_files(samples=30):
    """sweep.csv and robustness.json of a Latin hypercube sweep over a gain and the floor material."""
    lines = ["/AngularMotor/PID/Proportional,/Sim/Floor/Material,fitness,min_fitness,max_fitness,ok,jobs"]
    materials = ["PVC", "Wood", "Carpet"]
    for k in range(samples):
        gain = 10 + 30 * (k + 0.5) / samples
        fitness = -0.15 - (0.05 * (gain - 30) if gain > 30 else 0.0) - 0.02 * (k % 3)
        lines.append(f"{gain},{materials[k % 3]},{fitness},{fitness},{fitness},1,1")
    bins = [{"label": f"{low}..{low + 10}", "low": low, "high": low + 10, "count": 10, "mean": -0.15 - 0.1 * i}
            for i, low in enumerate((10, 20, 30))]
    report = {"title": "swing-robustness", "sampling": "lhs", "points": samples, "ok_points": samples,
              "sensitivity": [
                  {"path": "/AngularMotor/PID/Proportional", "kind": "numeric", "index": 0.5, "noise_floor": 0.1,
                   "bins": bins},
                  {"path": "/Sim/Floor/Material", "kind": "categorical", "index": 0.02, "noise_floor": 0.08,
                   "bins": [{"label": m, "low": i, "high": i, "count": 10, "mean": -0.2} for i, m in
                            enumerate(materials)]}],
              "ranking": ["/AngularMotor/PID/Proportional", "/Sim/Floor/Material"]}
    return "\n".join(lines) + "\n", json.dumps(report)


@unittest.skipUnless(HAVE_MATPLOTLIB, NO_MATPLOTLIB)
class SweepPlotTest(TempDirTest):
    def setUp(self):
        super().setUp()
        self.module = load_script("plot_sweep")

    def test_a_grid_sweep_names_its_scenario_units_and_direction(self):
        self.write("grid/sweep.csv", grid_sweep_csv())
        self.write("grid/robustness.json", json.dumps({"title": "swing-oscillator", "sampling": "grid"}))
        folder = os.path.join(self.dir, "grid")
        params, rows = self.module.read_sweep(os.path.join(folder, "sweep.csv"))
        figure = self.module.build_grid_figure(params, rows, self.module.read_report(folder), folder)
        self.assertEqual(figure._suptitle.get_text(), "swing-oscillator: fitness across 6 grid points (0 without an "
                                                      "ok run)")
        self.assertEqual([a.get_xlabel() for a in figure.axes], ["/Simulation/ODE/FrictionScaling (× friction "
                                                                 "coefficients)", "/AngularMotor/MaxVelocity (rad/s)"])
        self.assertEqual({a.get_ylabel() for a in figure.axes}, {"fitness (higher is better)"})
        self.assertEqual(sorted(legend_texts(figure)), ["grid point: mean over its repeats, bar min … max",
                                                        "mean over the other parameters"])
        self.assertEqual(legends_covering_axes(figure), [])
        # Without robustness.json (an older sweep) the folder names it.
        figure = self.module.build_grid_figure(params, rows, None, folder)
        self.assertTrue(figure._suptitle.get_text().startswith("grid: fitness across 6 grid points"))

    def test_a_one_parameter_sweep_says_what_its_line_is_and_its_title_fits(self):
        # Issue 52's paper cut: the legend said "mean over the other parameters" with no other parameter, and a long
        # scenario name ran off both ends of the 4.5-inch figure.
        self.write("one/sweep.csv", "/AngularMotor/PID/Proportional,fitness,min_fitness,max_fitness,ok,jobs\n"
                                    "10,-0.5,-0.6,-0.4,2,2\n20,-0.3,-0.35,-0.2,2,2\n30,-0.4,-0.5,-0.3,2,2\n")
        long_name = "a-rather-long-scenario-name-for-the-swing-oscillator-robustness"
        self.write("one/robustness.json", json.dumps({"title": long_name, "sampling": "grid"}))
        folder = os.path.join(self.dir, "one")
        params, rows = self.module.read_sweep(os.path.join(folder, "sweep.csv"))
        figure = self.module.build_grid_figure(params, rows, self.module.read_report(folder), folder)
        self.assertEqual(sorted(legend_texts(figure)), ["grid point: mean over its repeats, bar min … max",
                                                        "mean at each value"])
        figure.canvas.draw()
        renderer = figure.canvas.get_renderer()
        page = figure.bbox
        for artist in [figure._suptitle] + [legend for legend in figure.legends]:
            box = artist.get_window_extent(renderer)
            self.assertTrue(page.x0 <= box.x0 and box.x1 <= page.x1, f"{artist} runs off the figure: {box} of {page}")
        self.assertIn(long_name.split("-")[0], figure._suptitle.get_text())
        self.assertEqual(legends_covering_axes(figure), [])

    def test_a_hypercube_sweep_names_the_sensitivities_and_keeps_its_legend_off_the_data(self):
        csv_text, report = lhs_files()
        self.write("lhs/sweep.csv", csv_text)
        self.write("lhs/robustness.json", report)
        folder = os.path.join(self.dir, "lhs")
        params, rows = self.module.read_sweep(os.path.join(folder, "sweep.csv"))
        figure = self.module.build_lhs_figure(params, rows, self.module.read_report(folder), folder)
        self.assertEqual(figure._suptitle.get_text(),
                         "swing-robustness: fitness over 30 Latin hypercube samples (0 without an ok run)")
        visible = [a for a in figure.axes if a.get_visible()]
        self.assertEqual([a.get_title() for a in visible],
                         ["sensitivity S = 0.50 (noise floor 0.10)", "sensitivity S = 0.02 (noise floor 0.08)",
                          "first-order sensitivity of the fitness"])
        self.assertEqual(visible[0].get_xlabel(), "/AngularMotor/PID/Proportional (1/s)")
        self.assertEqual(visible[1].get_xlabel(), "/Sim/Floor/Material")
        self.assertEqual(visible[0].get_ylabel(), "fitness (higher is better)")
        self.assertEqual(sorted(legend_texts(figure)), ["first-order index S", "mean per bin", "mean per value",
                                                        "noise floor", "sample"])
        self.assertEqual(legends_covering_axes(figure), [])

    def test_the_command_orcs_batch_sweep_suggests(self):
        self.write("grid/sweep.csv", grid_sweep_csv())
        folder = os.path.join(self.dir, "grid")
        run = run_script("plot_sweep", folder)
        self.assertEqual(run.returncode, 0, run.stderr)
        self.assertIn(f"wrote {os.path.join(folder, 'sweep.png')}", run.stdout)
        self.assertTrue(is_png(os.path.join(folder, "sweep.png")))
        csv_text, report = lhs_files()
        self.write("lhs/sweep.csv", csv_text)
        self.write("lhs/robustness.json", report)
        out = os.path.join(self.dir, "lhs.png")
        code, _, err = call_main(self.module, os.path.join(self.dir, "lhs"), "--out", out)
        self.assertEqual(code, 0, err)
        self.assertTrue(is_png(out))


def gap_trace(phase=0.0, with_after=True, before_offset=0.0, samples=200):
    """As tests/clients/gap/plot_gap_test.cc writes it: a 1 Hz, 20° sine with a backlash-like error near reversals
    that `refit` lacks and `after` mostly has."""
    lines = [GAP_HEADER.strip()]
    for k in range(samples):
        t = k * 0.01
        x = 20.0 * math.sin(2 * math.pi * t + phase)
        v = 40.0 * math.pi * math.cos(2 * math.pi * t + phase)
        backlash = 0.6 * math.copysign(1.0, v) * math.exp(-abs(v) / 20.0)
        measured = x + backlash
        after = f"{x + 0.9 * backlash}" if with_after else ""
        lines.append(f"{t},{measured},{0.9 * x + before_offset},{x},{after},{x},{v},{abs(v)},0,0.1,{x - measured}")
    return "\n".join(lines) + "\n"


@unittest.skipUnless(HAVE_MATPLOTLIB, NO_MATPLOTLIB)
class GapPlotTest(TempDirTest):
    def setUp(self):
        super().setUp()
        self.module = load_script("plot_gap")

    def report(self, effect='"Backlash"', before_offset=0.0, with_after=True):
        self.write("report/report.json", '{"rig": "pendulum", "verdict": {"effect": ' + effect +
                   ', "text": "a test verdict", "quantity": "velocity"}, "worst_channels": ["Right/Knee", "Left/Hip"]}')
        for run in ("run1", "run2"):
            self.write(f"report/traces/{run}.Right_Knee.csv", gap_trace(0.0, with_after, before_offset))
            self.write(f"report/traces/{run}.Left_Hip.csv", gap_trace(1.0, with_after))
        return os.path.join(self.dir, "report")

    def channels(self, folder):
        _, effect, _, _, worst = self.module.read_report(os.path.join(folder, "report.json"))
        panels = []
        for motor in worst:
            files = self.module.trace_files(folder, motor)
            panels.append((motor, self.module.run_of(files[0], motor), self.module.read_trace(files[0])))
        return effect, panels

    def test_each_trace_has_a_residual_panel_below_it_on_the_same_time_axis(self):
        folder = self.report()
        effect, panels = self.channels(folder)
        figure = self.module.build_worst_channels_figure(panels, effect, "pendulum")
        self.assertEqual(len(figure.axes), 4, "a trace and a residual panel per channel")
        trace, residual = figure.axes[0], figure.axes[1]
        self.assertIn("pendulum", figure._suptitle.get_text())
        self.assertIn("missing effect Backlash", figure._suptitle.get_text())
        self.assertTrue(trace.get_title().startswith("Right/Knee, run run1 — RMS gap to measured: before"),
                        trace.get_title())
        self.assertEqual(trace.get_ylabel(), "joint angle (deg)")
        self.assertIn("measured − model", residual.get_title(loc="left"))
        self.assertEqual(residual.get_ylabel(), "measured −\nmodel (deg)")
        self.assertEqual(residual.get_xlabel(), "time (s)")
        self.assertIs(residual.get_shared_x_axes().joined(trace, residual), True)
        figure.canvas.draw()
        self.assertLess(residual.get_position().y1, trace.get_position().y0, "the residual panel is below")
        # The residual lines are measured − model, sample by sample.
        measured = panels[0][2]["measured"]
        refit = panels[0][2]["refit"]
        lines = residual.get_lines()[1:]  # after the zero line
        self.assertEqual(len(lines), 3)
        for got, m, r in zip(lines[1].get_ydata(), measured, refit):
            self.assertAlmostEqual(got, m - r)
        # Its y-range holds every model's gap (none is far off here), with little to spare.
        low, high = residual.get_ylim()
        largest = max(abs(m - v) for name in ("before", "refit", "after")
                      for m, v in zip(measured, panels[0][2][name]))
        self.assertGreaterEqual(high, largest)
        self.assertLessEqual(high, 1.2 * largest)
        self.assertAlmostEqual(low, -high)
        self.assertNotIn("off the scale", residual.get_title(loc="left"))
        self.assertEqual(legend_texts(figure), ["measured", "before (initial model)", "refit (base parameters)",
                                                "after (with Backlash)"])
        self.assertEqual(legends_covering_axes(figure), [])

    def test_a_model_far_off_does_not_squeeze_the_gap(self):
        folder = self.report(before_offset=400.0)
        effect, panels = self.channels(folder)
        figure = self.module.build_worst_channels_figure(panels, effect, "pendulum")
        trace, residual = figure.axes[0], figure.axes[1]
        low, high = trace.get_ylim()
        measured = panels[0][2]["measured"]
        self.assertLessEqual(low, min(measured))
        self.assertGreaterEqual(high, max(measured))
        self.assertLess(high - low, 2 * (max(measured) - min(measured)), "the range follows measured and after")
        self.assertIn("before leaves the plotted range", " ".join(trace.get_title().split()))
        self.assertIn("before off the scale", residual.get_title(loc="left"))
        self.assertLess(residual.get_ylim()[1], 10.0)
        # The other channel's before is near: it stays in its range.
        self.assertNotIn("leaves", figure.axes[2].get_title())
        before = panels[1][2]["before"]
        self.assertLessEqual(figure.axes[2].get_ylim()[0], min(before))

    def test_without_an_effect_the_refit_is_the_final_model(self):
        folder = self.report(effect="null", with_after=False)
        effect, panels = self.channels(folder)
        figure = self.module.build_worst_channels_figure(panels, effect, "pendulum")
        self.assertIn("no missing effect found", figure._suptitle.get_text())
        self.assertEqual(len(figure.axes[1].get_lines()), 3, "zero line, before and refit")
        self.assertIn("refit (base parameters; no effect won)", legend_texts(figure))
        self.assertEqual(legends_covering_axes(figure), [])

    def test_the_residual_plot_keeps_its_legend_off_the_data(self):
        folder = self.report()
        rig, effect, quantity, text, worst = self.module.read_report(os.path.join(folder, "report.json"))
        traces = [self.module.read_trace(p) for m in worst for p in self.module.trace_files(folder, m)]
        figure = self.module.build_residual_figure(traces, rig, effect, quantity, text)
        self.assertEqual(figure.axes[0].get_xlabel(), "velocity (deg/s)")
        self.assertEqual(figure.axes[0].get_ylabel(), "residual: measured − model (deg)")
        self.assertEqual(figure._suptitle.get_text(), "pendulum: missing effect Backlash; residual against velocity")
        self.assertEqual(legends_covering_axes(figure), [])

    def test_the_command_orcs_gap_suggests(self):
        folder = self.report()
        run = run_script("plot_gap", folder)
        self.assertEqual(run.returncode, 0, run.stderr)
        self.assertIn("residual_vs_velocity.png", run.stdout)
        for name in ("worst_channels.png", "residual_vs_velocity.png"):
            self.assertTrue(is_png(os.path.join(folder, "plots", name)), name)
        os.remove(os.path.join(folder, "report.json"))
        code, _, err = call_main(self.module, folder)
        self.assertEqual(code, 2)
        self.assertIn(os.path.join(folder, "report.json"), err)



@unittest.skipUnless(HAVE_MATPLOTLIB, NO_MATPLOTLIB)
class GeneralisationPlotTest(TempDirTest):
    """scripts/plot_generalisation.py: two evolutions' searches and their winners on unseen parameter sets."""

    def setUp(self):
        super().setUp()
        self.module = load_script("plot_generalisation")
        for name, best in (("same", [1.0, 2.0, 7.0]), ("fresh", [1.1, 3.9, 4.4])):
            rows = [f"{g},6,0,{b},0,0,0,{b},1.0" for g, b in enumerate(best)]
            self.write(f"{name}/fitness.csv", FITNESS_HEADER + "\n".join(rows) + "\n")
            # Two jobs of three sets; "same" falls in two sets, "fresh" in none.
            lines = []
            for job in range(2):
                sets = [{"index": k, "terms": {"sway": 0.6 - 0.1 * k + 0.01 * job,
                                               "falls": 1.0 if name == "same" and k == job else 0.0}}
                        for k in range(3)]
                lines.append(json.dumps({"id": f"job-{job}", "status": "ok", "sets": sets}))
            self.write(f"{name}/results.jsonl", "\n".join(lines) + "\n")

    def arguments(self):
        return ["--run", "same sets", os.path.join(self.dir, "same/fitness.csv"), os.path.join(self.dir, "same/results.jsonl"),
                "--run", "fresh sets", os.path.join(self.dir, "fresh/fitness.csv"),
                os.path.join(self.dir, "fresh/results.jsonl")]

    def test_every_set_is_a_point_falls_are_counted_and_no_legend_covers_data(self):
        runs = [("same sets", self.module.read_search(os.path.join(self.dir, "same/fitness.csv")),
                 self.module.read_sets(os.path.join(self.dir, "same/results.jsonl"), "sway")),
                ("fresh sets", self.module.read_search(os.path.join(self.dir, "fresh/fitness.csv")),
                 self.module.read_sets(os.path.join(self.dir, "fresh/results.jsonl"), "sway"))]
        self.assertEqual(len(runs[0][2]), 6)
        figure = self.module.build_figure(runs, "sway", "m", "a title")
        search, unseen = figure.axes
        self.assertEqual(search.get_ylabel(), "fitness (higher is better)")
        self.assertEqual(search.get_xlabel(), "generation")
        self.assertEqual(unseen.get_ylabel(), "sway (m, higher is better)")
        self.assertEqual(legend_texts(figure), ["same sets", "fresh sets", "same sets: 6 sets, 2 with a fall",
                                                "a set with a fall", "fresh sets: 6 sets, 0 with a fall"])
        self.assertEqual(legends_covering_axes(figure), [])
        points = [len(collection.get_offsets()) for collection in unseen.collections]
        self.assertEqual(points, [6, 2, 6], "every set a point, every fall a cross")
        figure.canvas.draw()
        ticks = [t for t in search.get_xticks() if search.get_xlim()[0] <= t <= search.get_xlim()[1]]
        self.assertTrue(all(float(t).is_integer() for t in ticks), ticks)

    def test_the_program_writes_a_png_and_bad_input_is_one_line_naming_the_line(self):
        out = os.path.join(self.dir, "figure.png")
        run = run_script("plot_generalisation", *self.arguments(), "--out", out)
        self.assertEqual(run.returncode, 0, run.stderr)
        self.assertTrue(is_png(out))
        self.write("same/results.jsonl", '{"sets": [{"terms": {"sway": 1}}]}\n{not json\n')
        code, _, err = call_main(self.module, *self.arguments(), "--out", out)
        self.assertEqual(code, 2)
        self.assertEqual(err, f"plot_generalisation.py: {os.path.join(self.dir, 'same/results.jsonl')}:2: not a JSON line\n")
        code, _, err = call_main(self.module, *self.arguments(), "--term", "height", "--out", out)
        self.assertEqual(code, 2)
        self.assertIn("results.jsonl:1: expected \"sets\" whose \"terms\" hold 'height'", err)



@unittest.skipUnless(HAVE_MATPLOTLIB, NO_MATPLOTLIB)
class ServoGainsPlotTest(TempDirTest):
    """scripts/plot_servo_gains.py: held-out errors of two orcs-gap reports beside published references."""

    def setUp(self):
        super().setUp()
        self.module = load_script("plot_servo_gains")
        for name, scale, effect in (("a", 1.0, "GearEfficiency"), ("b", 2.0, None)):
            runs = {}
            for version, factor in (("before", 3.0), ("refit", 2.0), ("after", 1.0)):
                runs[version] = {"runs": [{"run": "fit_run", "held_out": False, "mean_absolute_mrad": 5.0},
                                          {"run": "x_kp4", "held_out": True, "mean_absolute_mrad": 10 * factor * scale},
                                          {"run": "y_kp4", "held_out": True, "mean_absolute_mrad": 30 * factor * scale}]}
            self.write(f"{name}/report.json", json.dumps({"gap": runs, "verdict": {"effect": effect}}))

    def arguments(self):
        return ["--run", "one way", os.path.join(self.dir, "a"), "--run", "the other", os.path.join(self.dir, "b"),
                "--reference", "M1=50,90", "--reference", "M3=25,45"]

    def test_every_held_out_run_is_a_bar_the_references_are_lines_and_no_legend_covers_data(self):
        runs = [("one way", self.module.read_report(os.path.join(self.dir, "a"))),
                ("the other", self.module.read_report(os.path.join(self.dir, "b")))]
        figure = self.module.build_figure(runs, [("M1", [50.0, 90.0]), ("M3", [25.0, 45.0])])
        first, second = figure.axes
        self.assertEqual(first.get_ylabel(), "mean absolute position error (mrad, lower is better)")
        self.assertEqual(first.get_title(), "one way\nnamed effect: GearEfficiency")
        self.assertEqual(second.get_title(), "the other\nnamed effect: none")
        self.assertEqual([t.get_text() for t in first.get_xticklabels()], ["x", "y"])
        self.assertEqual(len(first.patches), 6, "two held-out runs × three model versions; the fit run is left out")
        self.assertIn("final model (mean 20.0)", legend_texts(figure))
        self.assertIn("M3 (mean of 4): 45.0", legend_texts(figure))
        self.assertEqual(legends_covering_axes(figure), [])

    def test_the_table_and_bad_input(self):
        out = os.path.join(self.dir, "figure.png")
        table = os.path.join(self.dir, "table.md")
        run = run_script("plot_servo_gains", *self.arguments(), "--out", out, "--table", table)
        self.assertEqual(run.returncode, 0, run.stderr)
        self.assertTrue(is_png(out))
        with open(table, encoding="utf-8") as f:
            text = f.read()
        self.assertIn("| one way | **mean** | **60.0** | **40.0** | **20.0** | GearEfficiency |", text)
        self.assertIn("| the other | M3 (mean, published) | | | 45.0 | |", text)
        self.write("b/report.json", "{}")
        code, _, err = call_main(self.module, *self.arguments(), "--out", out)
        self.assertEqual(code, 2)
        self.assertEqual(err, f"plot_servo_gains.py: {os.path.join(self.dir, 'b')}/report.json: not an orcs-gap report "
                              "(missing 'gap')\n")


@unittest.skipUnless(HAVE_MATPLOTLIB, NO_MATPLOTLIB)
class ComparePlotTest(TempDirTest):
    """scripts/plot_compare.py (orcs-batch compare): B against A with the line B = A, and each job's change."""

    CSV = ("job,status_a,status_b,fitness_a,fitness_b,fitness_delta\n"
           "job-0,ok,ok,1.0,1.0,0\n"
           "job-1,ok,ok,2.0,2.5,0.5\n"
           "job-2,ok,timeout,3.0,,\n"
           "job-3,ok,ok,4.0,3.0,-1\n")

    def test_the_figure_names_the_runs_counts_the_changes_and_says_which_way_is_better(self):
        module = load_script("plot_compare")
        jobs, a, b, missing = module.read(self.write("compare.csv", self.CSV))
        self.assertEqual((jobs, a, b, missing), (["job-0", "job-1", "job-3"], [1.0, 2.0, 4.0], [1.0, 2.5, 3.0], 1))
        fig = module.figure(jobs, a, b, missing, "A = ode, B = mujoco")
        left, right = fig.axes
        self.assertEqual(fig._suptitle.get_text(), "A = ode, B = mujoco")
        self.assertIn("higher is better", left.get_xlabel())
        self.assertIn("higher is better", left.get_ylabel())
        self.assertEqual(right.get_title(), "2 of 3 jobs changed; 1 without a fitness")
        self.assertIn("B − A", right.get_ylabel())
        self.assertEqual([round(p.get_height(), 6) for p in right.patches], [0.0, 0.5, -1.0])
        self.assertIn("B = A (unchanged)", legend_texts(fig))

    def test_a_file_that_is_not_a_compare_csv_is_exit_2_naming_it(self):
        path = self.write("other.csv", "time,value\n0,1\n")
        result = run_script("plot_compare", path)
        self.assertEqual(result.returncode, 2)
        self.assertIn(f"{path}:1: not a compare.csv", result.stderr)


if __name__ == "__main__":
    unittest.main()
