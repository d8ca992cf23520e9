#!/usr/bin/python3
"""Plots an orcs-gap report: where simulation and measurement disagree, and whether the named effect fixes it.

    scripts/plot_gap.py REPORT_DIR

Reads REPORT_DIR/report.json and REPORT_DIR/traces/<run>.<motor, / as _>.csv (written by orcs-gap) and writes
  REPORT_DIR/plots/worst_channels.png      one panel per worst channel (up to 4), its first run's trace (runs
                                           sorted by name; --run NAME shows that run's): measured (dark grey) against the initial model
                                           (before), the base parameters refitted (refit) and the model with
                                           the winning effect (after), the RMS of each in the title ("after" is
                                           the refit when no effect won); below it, on the same time axis, the
                                           residual measured − model. The y-range follows measured and the
                                           final model, so a model far off leaves it (the panel's title says so)
  REPORT_DIR/plots/residual_vs_<Q>.png     measured − refit and measured − after against the verdict's quantity
                                           Q, pooled over all runs of the worst channels, with the mean in bins:
                                           the effect's signature should be in the first and gone from the
                                           second. Without a winning effect Q is speed.
Exits 2 with a one-line message naming the file when report.json or a trace is missing or malformed.
Debian's python3-matplotlib; runs headless.
"""
import argparse
import csv
import glob
import json
import math
import os
import sys
import textwrap

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402 (after choosing the headless backend)

MAX_PANELS = 4
COLUMNS = ["time", "measured", "before", "refit", "after", "desired", "velocity", "speed", "acceleration", "load",
           "command_error"]
REQUIRED = ["time", "measured", "before", "refit"]  # never empty; the other columns may have empty cells
QUANTITIES = {  # verdict quantity → axis label
    "velocity": "velocity (deg/s)",
    "speed": "speed (deg/s)",
    "load": "load (N·m)",
    "acceleration": "acceleration (deg/s²)",
    "command_error": "command error: desired − measured (deg)",
    "time": "time (s)",
}
BINS = 24


def fail(message):
    print(f"plot_gap.py: {message}", file=sys.stderr)
    sys.exit(2)


def read_report(path):
    """Returns (rig, effect or None, quantity, verdict text, worst channel names); exits 2 naming the file on
    bad input."""
    try:
        with open(path) as handle:
            report = json.load(handle)
    except OSError as error:
        fail(f"{path}: {error.strerror}")
    except json.JSONDecodeError as error:
        fail(f"{path}:{error.lineno}: not valid JSON: {error.msg}")
    if not isinstance(report, dict):
        fail(f"{path}: expected a JSON object")
    verdict = report.get("verdict")
    if not isinstance(verdict, dict):
        fail(f"{path}: expected an object \"verdict\"")
    effect = verdict.get("effect")
    if effect is not None and not isinstance(effect, str):
        fail(f"{path}: verdict.effect: expected a string or null")
    quantity = verdict.get("quantity") if effect is not None else "speed"
    if quantity not in QUANTITIES:
        fail(f"{path}: verdict.quantity: expected one of {', '.join(QUANTITIES)}, found {quantity!r}")
    worst = report.get("worst_channels")
    if not isinstance(worst, list) or not worst or not all(isinstance(name, str) for name in worst):
        fail(f"{path}: expected \"worst_channels\", a non-empty list of motor names")
    rig = report.get("rig", "")
    text = verdict.get("text") or ""
    return (rig if isinstance(rig, str) else str(rig)), effect, quantity, str(text), worst


def number(text, path, line, column):
    if text == "":
        if column in REQUIRED:
            fail(f"{path}:{line}: column {column} is empty")
        return math.nan
    try:
        value = float(text)
    except ValueError:
        fail(f"{path}:{line}: column {column}: expected a number, found {text!r}")
    return value


def read_trace(path):
    """Returns {column: list of floats} (NaN for an empty cell); exits 2 naming the file and line on bad input."""
    try:
        with open(path, newline="") as handle:
            reader = csv.reader(handle)
            header = next(reader, None)
            if header != COLUMNS:
                fail(f"{path}:1: expected the header {','.join(COLUMNS)}")
            trace = {column: [] for column in COLUMNS}
            for line, fields in enumerate(reader, start=2):
                if len(fields) != len(COLUMNS):
                    fail(f"{path}:{line}: expected {len(COLUMNS)} fields, found {len(fields)}")
                for column, text in zip(COLUMNS, fields):
                    trace[column].append(number(text, path, line, column))
    except OSError as error:
        fail(f"{path}: {error.strerror}")
    if not trace["time"]:
        fail(f"{path}: no samples")
    return trace


def trace_files(folder, motor):
    """The trace files of `motor`, sorted by run; exits 2 naming the expected files when there are none."""
    suffix = f".{motor.replace('/', '_')}.csv"
    pattern = os.path.join(folder, "traces", "*" + suffix)
    files = sorted(glob.glob(os.path.join(glob.escape(os.path.join(folder, "traces")), "*" + glob.escape(suffix))))
    if not files:
        fail(f"{pattern}: no trace of worst channel {motor}")
    return files


def run_of(path, motor):
    return os.path.basename(path)[: -len(f".{motor.replace('/', '_')}.csv")]


def rms(measured, model):
    errors = [(m - s) ** 2 for m, s in zip(measured, model) if not math.isnan(s)]
    return math.sqrt(sum(errors) / len(errors)) if errors else math.nan


def has_after(trace):
    return any(not math.isnan(value) for value in trace["after"])


def save(figure, out):
    """Writes the figure to a temporary name and renames it, so that a half-written PNG never looks finished."""
    temporary = f"{out}.tmp.{os.getpid()}"
    figure.savefig(temporary, dpi=110, format="png")
    plt.close(figure)
    os.replace(temporary, out)


def finite(values):
    return [v for v in values if not math.isnan(v)]


def value_range(series):
    """(low, high) over the finite values of several lists, or None when there are none."""
    values = [v for values in series for v in finite(values)]
    return (min(values), max(values)) if values else None


def focused_limits(core, others, far=0.5, margin=0.06):
    """Y-limits that show the core series (measured and the final model) and take in each other series only when
    it extends their range by at most `far` of it on either side: a curve far away (the initial model of a badly
    wrong rig) would otherwise squeeze the gap into a line. Returns (low, high, names of the series left partly
    outside); others is {name: values}."""
    low, high = value_range(core) or (-1.0, 1.0)
    span = max(high - low, 1e-9)
    clipped = []
    for name, values in others.items():
        extent = value_range([values])
        if extent is None:
            continue
        if extent[0] >= low - far * span and extent[1] <= high + far * span:
            low, high = min(low, extent[0]), max(high, extent[1])
        else:
            clipped.append(name)
    span = max(high - low, 1e-9)
    return low - margin * span, high + margin * span, clipped


def residual_limits(core, others, factor=5.0):
    """Symmetric y-limits about 0 for residuals: the 99th percentile of |residual| over the core series, widened
    for another series only when its own is at most `factor` times that. Returns (limit, names left outside)."""
    def extent(values):
        magnitudes = sorted(abs(v) for v in finite(values))
        return magnitudes[min(len(magnitudes) - 1, int(0.99 * len(magnitudes)))] if magnitudes else 0.0
    limit = max([extent(values) for values in core] + [1e-6])
    clipped = []
    for name, values in others.items():
        other = extent(values)
        if other <= factor * limit:
            limit = max(limit, other)
        elif finite(values):
            clipped.append(name)
    return 1.12 * limit, clipped


def build_worst_channels_figure(channels, effect, rig=""):
    """channels: [(motor, run, trace)]. Per channel a trace panel (measured against the models) and below it, on
    the same time axis, a residual panel (measured − model); one legend below everything."""
    # Laid out in inches: a trace (2.4) close above its residual (1.1), then a spacer row (0.45) that, with the
    # gaps, holds the residual's time axis and the next trace's title; the suptitle above, the legend below.
    count = len(channels)
    rows = ([2.4, 1.1, 0.45] * count)[:-1]
    gap, bottom = 0.3, 0.95
    figure = plt.figure(figsize=(9, 1.0))
    grid = figure.add_gridspec(len(rows), 1, height_ratios=rows, hspace=gap / (sum(rows) / len(rows)), left=0.1,
                               right=0.98)
    trace_axes, residual_axes = [], []
    for k, (motor, run, trace) in enumerate(channels):
        axis = figure.add_subplot(grid[3 * k])
        lower = figure.add_subplot(grid[3 * k + 1], sharex=axis)
        trace_axes.append(axis)
        residual_axes.append(lower)
        time = trace["time"]
        final = "after" if has_after(trace) else "refit"
        models = [("before", "C0", "--", "before (initial model)")]
        models.append(("refit", "C1", "-", "refit (base parameters)" if final == "after"
                       else "refit (base parameters; no effect won)"))
        if final == "after":
            models.append(("after", "C3", "-", f"after (with {effect})"))
        core = [trace["measured"], trace[final]]
        low, high, clipped = focused_limits(core, {name: trace[name] for name, _, _, _ in models if name != final})
        axis.plot(time, trace["measured"], color="0.25", linewidth=0.8, label="measured", zorder=3)
        for name, colour, style, label in models:
            axis.plot(time, trace[name], color=colour, linewidth=1.0, linestyle=style, label=label)
        axis.set_ylim(low, high)
        rms_text = ", ".join(f"{name} {rms(trace['measured'], trace[name]):.2f}°" for name, _, _, _ in models)
        heading = f"{motor}, run {run} — RMS gap to measured: {rms_text}"
        if clipped:
            heading += f"; {' and '.join(clipped)} leave{'s' if len(clipped) == 1 else ''} the plotted range"
        axis.set_title("\n".join(textwrap.wrap(heading, 105)), fontsize="medium")
        axis.set_ylabel("joint angle (deg)")
        axis.grid(True, alpha=0.3)
        axis.tick_params(labelbottom=False)

        gaps = {name: [m - v for m, v in zip(trace["measured"], trace[name])] for name, _, _, _ in models}
        limit, clipped = residual_limits([gaps[final]] + ([gaps["refit"]] if final == "after" else []),
                                         {name: gaps[name] for name, _, _, _ in models})
        lower.axhline(0.0, color="0.3", linewidth=0.8)
        for name, colour, style, _ in models:
            lower.plot(time, gaps[name], color=colour, linewidth=0.9, linestyle=style)
        lower.set_ylim(-limit, limit)
        note = f" ({', '.join(clipped)} off the scale)" if clipped else ""
        lower.set_ylabel("measured −\nmodel (deg)")
        lower.set_title(f"residual: measured − model{note}", fontsize="small", loc="left")
        lower.set_xlabel("time (s)")
        lower.grid(True, alpha=0.3)
    title = f"{rig}: " if rig else ""
    title += "measured vs simulated joint angle"
    title += f", missing effect {effect}" if effect is not None else ", no missing effect found"
    top = 0.7 + 0.2 * trace_axes[0].get_title().count("\n")  # room for the suptitle and the first panel's title
    height = sum(rows) + gap * (len(rows) - 1) + top + bottom
    figure.set_size_inches(9, height)
    grid.update(top=1 - top / height, bottom=bottom / height)
    figure.suptitle(title, y=1 - 0.12 / height, va="top")
    handles, labels = trace_axes[0].get_legend_handles_labels()
    figure.legend(handles, labels, loc="lower center", ncol=min(4, len(labels)), fontsize="small", frameon=False,
                  bbox_to_anchor=(0.5, 0.0))
    return figure


def plot_worst_channels(channels, effect, out, rig=""):
    save(build_worst_channels_figure(channels, effect, rig), out)


def binned_means(xs, ys):
    """Mean of ys in BINS equal bins of xs (bins without points left out), for a line through a scatter."""
    points = [(x, y) for x, y in zip(xs, ys) if not (math.isnan(x) or math.isnan(y))]
    if len(points) < 2:
        return [], []
    low, high = min(x for x, _ in points), max(x for x, _ in points)
    if high <= low:
        return [], []
    sums, counts = [0.0] * BINS, [0] * BINS
    for x, y in points:
        b = min(BINS - 1, int((x - low) / (high - low) * BINS))
        sums[b] += y
        counts[b] += 1
    centres = [low + (b + 0.5) * (high - low) / BINS for b in range(BINS) if counts[b]]
    return centres, [sums[b] / counts[b] for b in range(BINS) if counts[b]]


def residuals(traces, model, quantity):
    xs, ys = [], []
    for trace in traces:
        for x, m, s in zip(trace[quantity], trace["measured"], trace[model]):
            if not (math.isnan(x) or math.isnan(s)):
                xs.append(x)
                ys.append(m - s)
    return xs, ys


def build_residual_figure(traces, rig, effect, quantity, text):
    figure, axis = plt.subplots(figsize=(8, 5.4))
    series = [("refit", "C1", "measured − refit (base parameters)")]
    if effect is not None and any(has_after(trace) for trace in traces):
        series.append(("after", "C3", f"measured − after (with {effect})"))
    for model, color, label in series:
        xs, ys = residuals(traces, model, quantity)
        axis.scatter(xs, ys, s=3, alpha=0.25, color=color, linewidths=0, rasterized=True)
        centres, means = binned_means(xs, ys)
        axis.plot(centres, means, color=color, linewidth=2.0, label=f"{label}, mean in bins")
    axis.axhline(0.0, color="0.3", linewidth=0.8)
    axis.set_xlabel(QUANTITIES[quantity])
    axis.set_ylabel("residual: measured − model (deg)")
    axis.grid(True, alpha=0.3)
    place = f"{rig}: " if rig else ""
    if effect is None:
        figure.suptitle(f"{place}no missing effect found; residual against speed")
    else:
        figure.suptitle(f"{place}missing effect {effect}; residual against {quantity}")
    if text:
        axis.set_title("\n".join(textwrap.wrap(text, 110)), fontsize="small")
    figure.tight_layout(rect=(0, 0.07, 1, 1))
    figure.legend(*axis.get_legend_handles_labels(), loc="lower center", ncol=1, fontsize="small", frameon=False,
                  bbox_to_anchor=(0.5, 0.0))
    return figure


def plot_residuals(traces, rig, effect, quantity, text, out):
    save(build_residual_figure(traces, rig, effect, quantity, text), out)




def main(argv=None):
    parser = argparse.ArgumentParser(description="Plot an orcs-gap report (REPORT_DIR/report.json, traces/).")
    parser.add_argument("folder", help="the report folder orcs-gap wrote")
    parser.add_argument("--run", help="show this run's trace in the panels (default: the first run by name)")
    arguments = parser.parse_args(argv)
    rig, effect, quantity, text, worst = read_report(os.path.join(arguments.folder, "report.json"))
    panels, pooled = [], []
    for motor in worst:
        files = trace_files(arguments.folder, motor)
        traces = [read_trace(path) for path in files]
        shown = 0
        if arguments.run is not None:
            runs = [run_of(path, motor) for path in files]
            if arguments.run not in runs:
                fail(f"--run {arguments.run}: no such run in {arguments.folder}/traces (runs: {', '.join(runs)})")
            shown = runs.index(arguments.run)
        if len(panels) < MAX_PANELS:
            panels.append((motor, run_of(files[shown], motor), traces[shown]))
        pooled.extend(traces)
    plots = os.path.join(arguments.folder, "plots")
    os.makedirs(plots, exist_ok=True)
    worst_png = os.path.join(plots, "worst_channels.png")
    residual_png = os.path.join(plots, f"residual_vs_{quantity}.png")
    plot_worst_channels(panels, effect, worst_png, rig)
    plot_residuals(pooled, rig, effect, quantity, text, residual_png)
    print(f"plot_gap.py: wrote {worst_png} and {residual_png}")


if __name__ == "__main__":
    main()
