#!/usr/bin/python3
"""Plots an orcs-batch sweep: fitness against each swept parameter (docs/batch.md).

    scripts/plot_sweep.py DIR [--out FILE.png]

Reads DIR/sweep.csv (written by `orcs-batch sweep`) and writes DIR/sweep.png (or --out).

A grid sweep: one panel per swept parameter, every grid point's fitness as a dot (its min-max range over the
repeats as a bar) and, through them, the mean fitness at each value of that parameter over all values of the
others.

A Latin hypercube sweep (`--sample lhs`, recognised by DIR/robustness.json): one panel per parameter with every
sample's fitness as a dot and the mean fitness of each bin the sensitivity estimator used (a line over a numeric
parameter's bins, a marker per category), then a bar chart of the first-order sensitivity indices S with each
one's noise floor.

Categorical parameters (floor materials) are plotted at one x position per value. Points without an ok repeat
are left out. Debian's python3-matplotlib; runs headless.
"""
import argparse
import csv
import json
import math
import os
import sys
import textwrap

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402 (after choosing the headless backend)

RESULT_COLUMNS = ["fitness", "min_fitness", "max_fitness", "ok", "jobs"]
FITNESS_LABEL = "fitness (higher is better)"
# Units of the parameters commonly swept (model/aseries/dynamixel_motor.h, docs/model.md), for the x axes.
PARAMETER_UNITS = {
    "/AngularMotor/PID/Proportional": "1/s",
    "/AngularMotor/PID/Integral": "s",
    "/AngularMotor/PID/Differential": "s",
    "/AngularMotor/FMaxFactor": "N·m",
    "/AngularMotor/MaxVelocity": "rad/s",
    "/AngularMotor/StaticFriction": "N·m",
    "/AngularMotor/StaticFrictionBorder": "rad/s",
    "/AngularMotor/DynamicFriction": "N·m·s/rad",
    "/AngularMotor/DynamicFrictionOffset": "N·m",
    "/AngularMotor/MotorNoise": "rad/s",
    "/Simulation/ODE/FrictionScaling": "× friction coefficients",
    "/Simulation/ODE/StaticFrictionSpeed": "m/s",
    "/Simulation/MuJoCo/ContactTimeConstant": "s",
    "/Simulation/TimeStepSize": "s",
}


def fail(message):
    print(f"plot_sweep.py: {message}", file=sys.stderr)
    sys.exit(2)


def number_or_text(field):
    try:
        return float(field)
    except ValueError:
        return field


def read_sweep(path):
    """Returns (parameter paths, rows as dicts); the result columns are floats or None, a parameter's values floats
    or, for a category, text. Exits 2 naming the line on bad input."""
    try:
        with open(path, newline="") as handle:
            reader = csv.reader(handle)
            header = next(reader, None)
            if not header or header[-5:] != RESULT_COLUMNS:
                fail(f"{path}:1: expected a header ending in {','.join(RESULT_COLUMNS)}")
            params = header[:-5]
            if not params:
                fail(f"{path}:1: no swept parameter in the header")
            rows = []
            for number, fields in enumerate(reader, start=2):
                if len(fields) != len(header):
                    fail(f"{path}:{number}: expected {len(header)} fields, found {len(fields)}")
                try:
                    results = [float(f) if f != "" else None for f in fields[-5:]]
                except ValueError as error:
                    fail(f"{path}:{number}: {error}")
                row = dict(zip(header, [number_or_text(f) for f in fields[:-5]] + results))
                row.update({("text", p): f for p, f in zip(params, fields)})  # a category's name as written
                rows.append(row)
    except OSError as error:
        fail(f"{path}: {error.strerror}")
    return params, rows


def read_report(folder):
    """DIR/robustness.json as a dict, or None when there is none (an older sweep)."""
    path = os.path.join(folder, "robustness.json")
    if not os.path.exists(path):
        return None
    try:
        with open(path) as handle:
            return json.load(handle)
    except (OSError, ValueError) as error:
        fail(f"{path}: {error}")


def categories_of(param, rows, report):
    """The categories of a categorical parameter in the axis's order, or None for a numeric one."""
    entry = next((s for s in (report or {}).get("sensitivity", []) if s["path"] == param), None)
    if entry is not None and entry["kind"] == "categorical":
        return [b["label"] for b in entry["bins"]] + sorted(
            {r[("text", param)] for r in rows} - {b["label"] for b in entry["bins"]})
    if all(isinstance(r[param], float) for r in rows):
        return None
    seen = []
    for r in rows:
        if r[("text", param)] not in seen:
            seen.append(r[("text", param)])
    return seen


def x_positions(param, rows, categories, jitter=0.0):
    """Numbers as they are; categories at their index, spread by up to ±jitter (deterministically) so that many
    samples of one category do not hide each other."""
    if categories is None:
        return [r[param] for r in rows]
    index = {c: i for i, c in enumerate(categories)}
    return [index[r[("text", param)]] + jitter * (((i * 0.6180339887) % 1.0) - 0.5) for i, r in enumerate(rows)]


def parameter_label(param):
    unit = PARAMETER_UNITS.get(param)
    return f"{param} ({unit})" if unit else param


def legend_below(figure, axes_list, columns=4):
    """One legend for the whole figure below its panels (entries gathered from every panel, each label once), so
    that it covers no data. Call after tight_layout; it makes room at the bottom."""
    entries = {}
    for axis in axes_list:
        for handle, label in zip(*axis.get_legend_handles_labels()):
            entries.setdefault(label, handle)
    if not entries:
        return None
    height = figure.get_figheight()
    rows = math.ceil(len(entries) / columns)
    room = (0.3 * rows + 0.1) / height
    figure.subplots_adjust(bottom=figure.subplotpars.bottom + room)
    return figure.legend(list(entries.values()), list(entries), loc="lower center", ncol=min(columns, len(entries)),
                         fontsize="small", frameon=False, bbox_to_anchor=(0.5, 0.0))


def label_categories(axis, categories):
    if categories is not None:
        axis.set_xticks(range(len(categories)))
        axis.set_xticklabels(categories)


def wrapped(title, figure):
    """The title in lines that fit the figure's width (about 9 characters an inch at the default size)."""
    return "\n".join(textwrap.wrap(title, max(30, int(9 * figure.get_figwidth()))))


def sweep_title(report, folder):
    """The scenario's name (robustness.json's title), else the folder's name."""
    title = (report or {}).get("title")
    return str(title) if title else os.path.basename(os.path.normpath(folder or "sweep"))


def build_grid_figure(params, rows, report, folder=None):
    figure, axes = plt.subplots(1, len(params), figsize=(4.5 * len(params), 3.9), squeeze=False)
    ok_rows = [r for r in rows if r["fitness"] is not None and math.isfinite(r["fitness"])]
    repeats = max([int(r["jobs"]) for r in rows if r["jobs"] is not None] or [1])
    for axis, param in zip(axes[0], params):
        categories = categories_of(param, rows, report)
        xs = x_positions(param, ok_rows, categories)
        ys = [r["fitness"] for r in ok_rows]
        low = [r["fitness"] - r["min_fitness"] for r in ok_rows]
        high = [r["max_fitness"] - r["fitness"] for r in ok_rows]
        point = "grid point: mean over its repeats, bar min … max" if repeats > 1 else "grid point"
        axis.errorbar(xs, ys, yerr=[low, high], fmt="o", markersize=4, alpha=0.6, capsize=2, label=point)
        by_value = {}
        for x, y in zip(xs, ys):
            by_value.setdefault(x, []).append(y)
        values = sorted(by_value)
        # With one parameter there are no others: the line joins each value's mean over its repeats.
        joined = "mean over the other parameters" if len(params) > 1 else (
            "mean at each value" if repeats > 1 else "the grid points joined")
        axis.plot(values, [sum(by_value[v]) / len(by_value[v]) for v in values], "-", color="C3", label=joined)
        label_categories(axis, categories)
        axis.set_xlabel(parameter_label(param))
        axis.set_ylabel(FITNESS_LABEL)
        axis.grid(True, alpha=0.3)
    # Wrapped to the figure's width: a one-parameter figure is 4.5 inches wide, and a long scenario name was cut.
    title = (f"{sweep_title(report, folder)}: fitness across {len(rows)} grid points "
             f"({len(rows) - len(ok_rows)} without an ok run)")
    figure.suptitle(wrapped(title, figure))
    figure.tight_layout()
    legend_below(figure, axes[0], columns=2 if len(params) > 1 else 1)  # one narrow panel: one column
    return figure


def plot_grid(params, rows, out, report, folder=None):
    figure = build_grid_figure(params, rows, report, folder)
    figure.savefig(out, dpi=110)
    plt.close(figure)


def plot_bins(axis, entry, categories):
    """The bin means the sensitivity estimator used: a step line over numeric bins, a marker per category."""
    bins = entry["bins"]
    if categories is not None:
        index = {c: i for i, c in enumerate(categories)}
        axis.plot([index[b["label"]] for b in bins], [b["mean"] for b in bins], "D", color="C3", markersize=8,
                  label="mean per value")
        return
    for k, b in enumerate(bins):
        axis.plot([b["low"], b["high"]], [b["mean"], b["mean"]], "-", color="C3", linewidth=2.5,
                  label="mean per bin" if k == 0 else None)
    axis.plot([(b["low"] + b["high"]) / 2 for b in bins], [b["mean"] for b in bins], ":", color="C3", linewidth=1)


def build_lhs_figure(params, rows, report, folder=None):
    sensitivity = {s["path"]: s for s in report["sensitivity"]}
    panels = len(params) + 1
    columns = panels if panels <= 3 else math.ceil(panels / 2)  # four panels and more: two rows
    lines = math.ceil(panels / columns)
    figure, grid = plt.subplots(lines, columns, figsize=(4.6 * columns, 3.7 * lines + 0.4), squeeze=False)
    axes = [axis for line in grid for axis in line]
    for unused in axes[panels:]:
        unused.set_visible(False)
    ok_rows = [r for r in rows if r["fitness"] is not None and math.isfinite(r["fitness"])]
    for axis, param in zip(axes, params):
        categories = categories_of(param, rows, report)
        axis.plot(x_positions(param, ok_rows, categories, jitter=0.5), [r["fitness"] for r in ok_rows], "o",
                  markersize=3.5, alpha=0.5, label="sample")
        if param in sensitivity:
            plot_bins(axis, sensitivity[param], categories)
            index = sensitivity[param]["index"]
            floor = sensitivity[param].get("noise_floor")
            text = f"sensitivity S = {index:.2f}" if index is not None else "sensitivity S undefined"
            if floor is not None:
                text += f" (noise floor {floor:.2f})"
            axis.set_title(text, fontsize="medium")
        label_categories(axis, categories)
        axis.set_xlabel(parameter_label(param))
        axis.set_ylabel(FITNESS_LABEL)
        axis.grid(True, alpha=0.3)
    bars = axes[len(params)]
    ranked = [sensitivity[p] for p in report["ranking"]]
    names = [s["path"].rsplit("/", 2)[-2] + "/" + s["path"].rsplit("/", 1)[-1] for s in ranked]
    bars.bar(range(len(ranked)), [s["index"] or 0.0 for s in ranked], color="C0", label="first-order index S")
    bars.plot(range(len(ranked)), [s["noise_floor"] for s in ranked], "_", color="k", markersize=20,
              markeredgewidth=2, label="noise floor")
    bars.set_xticks(range(len(ranked)))
    bars.set_xticklabels(names, rotation=20, ha="right", fontsize="small")
    bars.set_ylim(0, 1)
    bars.set_ylabel("first-order index S")
    bars.set_title("first-order sensitivity of the fitness", fontsize="medium")
    bars.grid(True, axis="y", alpha=0.3)
    figure.suptitle(wrapped(f"{sweep_title(report, folder)}: fitness over {len(rows)} Latin hypercube samples "
                            f"({len(rows) - len(ok_rows)} without an ok run)", figure))
    figure.tight_layout()
    legend_below(figure, axes[:panels], columns=5)
    return figure


def plot_lhs(params, rows, out, report, folder=None):
    figure = build_lhs_figure(params, rows, report, folder)
    figure.savefig(out, dpi=110)
    plt.close(figure)




def main(argv=None):
    parser = argparse.ArgumentParser(description="Plot an orcs-batch sweep (DIR/sweep.csv).")
    parser.add_argument("folder", help="the sweep's output folder (orcs-batch sweep --out)")
    parser.add_argument("--out", help="the PNG to write (default DIR/sweep.png)")
    arguments = parser.parse_args(argv)
    params, rows = read_sweep(os.path.join(arguments.folder, "sweep.csv"))
    report = read_report(arguments.folder)
    out = arguments.out or os.path.join(arguments.folder, "sweep.png")
    if report is not None and report.get("sampling") == "lhs":
        plot_lhs(params, rows, out, report, arguments.folder)
    else:
        plot_grid(params, rows, out, report, arguments.folder)
    print(f"plot_sweep.py: wrote {out}")


if __name__ == "__main__":
    main()
