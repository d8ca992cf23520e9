#!/usr/bin/python3
"""Plots `orcs-batch compare A B`: the same jobs' fitness in two runs (docs/batch.md, "Comparing two runs").

    scripts/plot_compare.py DIR/compare.csv [--out FILE.png] [--a NAME] [--b NAME]

Reads compare.csv (written by orcs-batch compare) and writes compare.png beside it (or --out): on the left each
job's fitness in B against its fitness in A, with the line B = A where unchanged jobs lie; on the right each job's
change B − A in job order, so a reader sees at once how many jobs moved, which way and by how much. Jobs that
failed in either run have no fitness and are counted in the title. Debian's python3-matplotlib; runs headless.
"""
import argparse
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402 (after choosing the headless backend)
from matplotlib.ticker import MaxNLocator  # noqa: E402


def fail(message):
    print(f"plot_compare.py: {message}", file=sys.stderr)
    sys.exit(2)


def read(path):
    """(job ids, fitness in A, fitness in B, jobs without a fitness in one run) from compare.csv."""
    try:
        with open(path, newline="") as f:
            rows = list(csv.reader(f))
    except OSError as error:
        fail(f"{path}: cannot read it: {error.strerror}")
    if not rows or rows[0][:6] != ["job", "status_a", "status_b", "fitness_a", "fitness_b", "fitness_delta"]:
        fail(f"{path}:1: not a compare.csv (expected the header job,status_a,status_b,fitness_a,fitness_b,...)")
    jobs, a, b, missing = [], [], [], 0
    for number, row in enumerate(rows[1:], start=2):
        if len(row) < 6:
            fail(f"{path}:{number}: {len(row)} fields, expected at least 6")
        if row[3] == "" or row[4] == "":
            missing += 1
            continue
        try:
            a.append(float(row[3]))
            b.append(float(row[4]))
        except ValueError:
            fail(f"{path}:{number}: fitness_a or fitness_b is not a number")
        jobs.append(row[0])
    return jobs, a, b, missing


def figure(jobs, a, b, missing, title):
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.6), constrained_layout=True)
    fig.suptitle(title)
    changed = sum(1 for x, y in zip(a, b) if x != y)
    if a:
        low, high = min(a + b), max(a + b)
        pad = 0.05 * (high - low or 1.0)
        left.plot([low - pad, high + pad], [low - pad, high + pad], color="0.6", linewidth=1, label="B = A (unchanged)")
    left.scatter(a, b, s=14, color="tab:blue", label=f"a job ({len(a)})", zorder=3)
    left.set_xlabel("fitness in A (higher is better)")
    left.set_ylabel("fitness in B (higher is better)")
    left.set_title("each job's fitness in both runs")
    left.legend(loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=2, frameon=False)
    left.grid(alpha=0.3)
    deltas = [y - x for x, y in zip(a, b)]
    colours = ["tab:green" if d > 0 else "tab:red" if d < 0 else "0.6" for d in deltas]
    right.bar(range(len(deltas)), deltas, color=colours, width=0.8)
    right.axhline(0.0, color="0.3", linewidth=0.8)
    right.set_xlabel("job, in A's order" + (f" (first {jobs[0]}, last {jobs[-1]})" if jobs else ""))
    right.set_ylabel("fitness change B − A (higher: B better)")
    right.set_title(f"{changed} of {len(deltas)} jobs changed" + (f"; {missing} without a fitness" if missing else ""))
    right.grid(alpha=0.3, axis="y")
    right.xaxis.set_major_locator(MaxNLocator(integer=True))
    return fig


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("csv", help="compare.csv written by orcs-batch compare")
    parser.add_argument("--out", help="the PNG (default: compare.png beside the CSV)")
    parser.add_argument("--a", default="A", help="what run A is, for the title (orcs-batch compare: its results file)")
    parser.add_argument("--b", default="B", help="what run B is")
    args = parser.parse_args(argv)
    jobs, a, b, missing = read(args.csv)
    out = args.out or os.path.join(os.path.dirname(os.path.abspath(args.csv)), "compare.png")
    fig = figure(jobs, a, b, missing, f"The same jobs in two runs: A = {args.a}, B = {args.b}")
    fig.savefig(out, dpi=100)
    print(f"plot_compare.py: wrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
