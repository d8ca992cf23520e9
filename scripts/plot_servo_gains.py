#!/usr/bin/python3
"""The real-servo result of docs/gap.md ("A real servo"): a model fitted at one firmware gain, scored at another.

    scripts/plot_servo_gains.py --run LABEL REPORT_DIR [--run LABEL REPORT_DIR] [--reference LABEL=MRAD,MRAD ...]
                                --out FIG.png [--table TABLE.md]

Each --run is an orcs-gap report folder (its report.json) whose held-out runs are at another firmware gain than
its fit runs. The figure has one panel per report: the mean absolute position error (mrad, BAM's metric) of every
held-out run under the model as given, the base parameters refitted and the final model (with the named effect,
if any), and each --reference as a dashed line at its mean for that report (in --run order, e.g. the published
BAM models). --table writes the markdown table of the same numbers. Bad input exits 2 with one line naming the
file. Needs matplotlib (Debian's python3-matplotlib).
"""
import argparse
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402 (after choosing the headless backend)

VERSIONS = [("before", "as given", "tab:grey"), ("refit", "base refitted", "tab:blue"),
            ("after", "final model", "tab:green")]
REFERENCE_STYLES = [("tab:red", "--"), ("tab:purple", ":")]


def fail(message):
    print(f"plot_servo_gains.py: {message}", file=sys.stderr)
    sys.exit(2)


def read_report(folder):
    path = f"{folder}/report.json"
    try:
        with open(path, encoding="utf-8") as f:
            report = json.load(f)
    except OSError as error:
        fail(f"{path}: cannot read: {error.strerror}")
    except json.JSONDecodeError as error:
        fail(f"{path}:{error.lineno}: malformed JSON: {error.msg}")
    try:
        runs = {}
        for version, _, _ in VERSIONS:
            for run in report["gap"][version]["runs"]:
                if run["held_out"]:
                    runs.setdefault(run["run"], {})[version] = run["mean_absolute_mrad"]
        effect = report["verdict"]["effect"]
    except (KeyError, TypeError) as error:
        fail(f"{path}: not an orcs-gap report (missing {error})")
    if not runs:
        fail(f"{path}: no held-out runs")
    return {"path": path, "runs": runs, "effect": effect or "none"}


def mean(values):
    numbers = [v for v in values if v is not None]
    return sum(numbers) / len(numbers) if numbers else float("nan")


def parse_reference(text):
    label, _, numbers = text.partition("=")
    try:
        values = [float(v) for v in numbers.split(",")]
    except ValueError:
        fail(f"--reference {text!r}: expected LABEL=MRAD[,MRAD...]")
    if not label or not values:
        fail(f"--reference {text!r}: expected LABEL=MRAD[,MRAD...]")
    return label, values


def table(runs, references):
    lines = ["| fitted → held out | held-out run | as given | base refitted | final model | named effect |",
             "|---|---|---|---|---|---|"]
    for index, (label, report) in enumerate(runs):
        for name, values in sorted(report["runs"].items()):
            cells = [f"{values.get(v):.1f}" if values.get(v) is not None else "failed" for v, _, _ in VERSIONS]
            lines.append(f"| {label} | {name} | " + " | ".join(cells) + f" | {report['effect']} |")
        means = [mean([r.get(v) for r in report["runs"].values()]) for v, _, _ in VERSIONS]
        lines.append(f"| {label} | **mean** | " + " | ".join(f"**{m:.1f}**" for m in means) +
                     f" | {report['effect']} |")
        for ref_label, values in references:
            if index < len(values):
                lines.append(f"| {label} | {ref_label} (mean, published) | | | {values[index]:.1f} | |")
    return "\n".join(lines) + "\n"


def build_figure(runs, references):
    figure, axes = plt.subplots(1, len(runs), figsize=(6.2 * len(runs), 5.4), squeeze=False)
    for index, (label, report) in enumerate(runs):
        ax = axes[0][index]
        names = sorted(report["runs"])
        width = 0.8 / len(VERSIONS)
        top = 0.0
        for k, (version, version_label, colour) in enumerate(VERSIONS):
            values = [report["runs"][n].get(version) or 0.0 for n in names]
            top = max(top, max(values))
            positions = [i + (k - 1) * width for i in range(len(names))]
            ax.bar(positions, values, width, color=colour,
                   label=f"{version_label} (mean {mean([report['runs'][n].get(version) for n in names]):.1f})")
        for (ref_label, values), (colour, style) in zip(references, REFERENCE_STYLES):
            if index < len(values):
                ax.axhline(values[index], color=colour, linestyle=style, linewidth=1.5,
                           label=f"{ref_label} (mean of 4): {values[index]:.1f}")
                top = max(top, values[index])
        ax.set_xticks(range(len(names)))
        ax.set_xticklabels([n.rsplit("_kp", 1)[0] for n in names], rotation=15)
        ax.set_ylim(0, top * 1.1)
        ax.set_ylabel("mean absolute position error (mrad, lower is better)")
        ax.set_title(f"{label}\nnamed effect: {report['effect']}")
        ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.2), fontsize=8, ncol=2, frameon=False)
    figure.suptitle("XL330 pendulum: a model fitted at one firmware gain, scored on the four runs at the other")
    figure.tight_layout()
    return figure


def plot(runs, references, out):
    build_figure(runs, references).savefig(out, dpi=110)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--run", nargs=2, action="append", metavar=("LABEL", "REPORT_DIR"), required=True)
    parser.add_argument("--reference", action="append", default=[], metavar="LABEL=MRAD,MRAD")
    parser.add_argument("--out", required=True)
    parser.add_argument("--table")
    args = parser.parse_args(argv)
    runs = [(label, read_report(folder)) for label, folder in args.run]
    references = [parse_reference(text) for text in args.reference]
    plot(runs, references, args.out)
    if args.table:
        with open(args.table, "w", encoding="utf-8") as f:
            f.write(table(runs, references))


if __name__ == "__main__":
    main()
