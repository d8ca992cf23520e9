#!/usr/bin/python3
"""Plots an orcs-batch evolve run: fitness per generation (docs/evolution.md).

    scripts/plot_evolution.py DIR [--out FILE.png] [--title TEXT]

Reads DIR/fitness.csv (written by `orcs-batch evolve` after every generation) and writes DIR/fitness.png (or
--out): the best fitness found so far, each generation's best and median, and the band between its worst and
best, against the generation; the legend sits below the axes. The title names the scenario, algorithm and
population (from DIR/checkpoint.json). orcs-batch evolve calls it at the end of a run. Debian's
python3-matplotlib; runs headless.
"""
import argparse
import csv
import json
import os
import sys
import textwrap

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402 (after choosing the headless backend)
from matplotlib.ticker import MaxNLocator  # noqa: E402

COLUMNS = ["generation", "evaluations", "failed", "best", "mean", "median", "worst", "best_so_far", "seconds"]


def fail(message):
    print(f"plot_evolution.py: {message}", file=sys.stderr)
    sys.exit(2)


def number(text, path, line, column):
    """A float, or None for an empty field (a generation without ok jobs)."""
    if text == "":
        return None
    try:
        return float(text)
    except ValueError:
        fail(f"{path}:{line}: column '{column}' is not a number: {text!r}")


def read_history(path):
    """Rows of fitness.csv as dicts; exits 2 naming the line on bad input."""
    try:
        with open(path, newline="") as handle:
            reader = csv.reader(handle)
            if next(reader, None) != COLUMNS:
                fail(f"{path}:1: expected the header {','.join(COLUMNS)}")
            rows = []
            for line, fields in enumerate(reader, start=2):
                if len(fields) != len(COLUMNS):
                    fail(f"{path}:{line}: expected {len(COLUMNS)} fields, found {len(fields)}")
                rows.append({c: number(f, path, line, c) for c, f in zip(COLUMNS, fields)})
    except OSError as error:
        fail(f"{path}: {error.strerror}")
    if not rows:
        fail(f"{path}: no generation yet")
    return rows


def default_title(folder):
    """'SCENARIO: fitness per generation (ALGORITHM, P genomes per generation)' from DIR/checkpoint.json, which
    orcs-batch evolve writes beside fitness.csv; the folder's name when there is none or it cannot be read."""
    name = os.path.basename(os.path.normpath(folder))
    try:
        with open(os.path.join(folder, "checkpoint.json")) as handle:
            fingerprint = json.load(handle)["fingerprint"]
        scenario = str(fingerprint["scenario"])
        settings = []
        if fingerprint.get("algorithm"):
            settings.append(str(fingerprint["algorithm"]))
        if isinstance(fingerprint.get("population"), int):
            settings.append(f"{fingerprint['population']} genomes per generation")
    except (OSError, ValueError, KeyError, TypeError):
        return f"{name}: fitness per generation"
    return f"{scenario}: fitness per generation" + (f" ({', '.join(settings)})" if settings else "")


def build_figure(rows, title):
    """The figure: the band between each generation's worst and best, its median and best, and the best so far,
    against whole-numbered generations; the legend below the axes, off the data."""
    figure, axes = plt.subplots(figsize=(7, 4.8))
    generations = [r["generation"] for r in rows]
    band = [r for r in rows if r["worst"] is not None]
    axes.fill_between([r["generation"] for r in band], [r["worst"] for r in band], [r["best"] for r in band],
                      color="tab:blue", alpha=0.15, label="generation: worst … best")
    axes.plot([r["generation"] for r in band], [r["median"] for r in band], color="tab:blue", lw=1,
              label="generation median")
    axes.plot([r["generation"] for r in band], [r["best"] for r in band], "o", color="tab:blue", ms=3, zorder=3,
              label="generation best")
    # Centred on each generation ("mid"): the last generation's value has a level of its own, so a gain in it shows
    # (with "post" the line ended in a bare rise at the last generation, its gain easily missed at the axis' edge).
    axes.step(generations, [r["best_so_far"] for r in rows], where="mid", color="tab:red", lw=2,
              label="best so far")
    axes.set_xlabel("generation")
    axes.set_ylabel("fitness (higher is better)")
    axes.xaxis.set_major_locator(MaxNLocator(integer=True))
    axes.set_title("\n".join(textwrap.wrap(title, 80)), fontsize="medium")
    axes.grid(alpha=0.3)
    axes.legend(loc="upper center", bbox_to_anchor=(0.5, -0.14), ncol=2, fontsize=8, frameon=False)
    figure.tight_layout()
    return figure


def plot(rows, out, title):
    figure = build_figure(rows, title)
    figure.savefig(out, dpi=110)
    plt.close(figure)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("folder", help="an orcs-batch evolve output folder (with fitness.csv)")
    parser.add_argument("--out", help="the picture (default FOLDER/fitness.png)")
    parser.add_argument("--title", help="the plot's title (default: the scenario, algorithm and population from "
                        "DIR/checkpoint.json, else the folder's name)")
    args = parser.parse_args(argv)
    rows = read_history(os.path.join(args.folder, "fitness.csv"))
    out = args.out or os.path.join(args.folder, "fitness.png")
    plot(rows, out, args.title or default_title(args.folder))
    print(f"plot_evolution.py: {out}")


if __name__ == "__main__":
    main()
