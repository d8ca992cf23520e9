#!/usr/bin/python3
"""Plots an orcs-batch sweep: fitness against each swept parameter (docs/batch.md).

    scripts/plot_sweep.py DIR [--out FILE.png]

Reads DIR/sweep.csv (written by `orcs-batch sweep`) and writes DIR/sweep.png (or --out): one panel per swept
parameter, every grid point's fitness as a dot (its min-max range over the repeats as a bar) and, through them,
the mean fitness at each value of that parameter over all values of the others. Points without an ok repeat
are left out. Debian's python3-matplotlib; runs headless.
"""
import argparse
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402 (after choosing the headless backend)


def fail(message):
    print(f"plot_sweep.py: {message}", file=sys.stderr)
    sys.exit(2)


def read_sweep(path):
    """Returns (parameter paths, rows as dicts of floats or None); exits 2 naming the line on bad input."""
    try:
        with open(path, newline="") as handle:
            reader = csv.reader(handle)
            header = next(reader, None)
            if not header or header[-5:] != ["fitness", "min_fitness", "max_fitness", "ok", "jobs"]:
                fail(f"{path}:1: expected a header ending in fitness,min_fitness,max_fitness,ok,jobs")
            params = header[:-5]
            if not params:
                fail(f"{path}:1: no swept parameter in the header")
            rows = []
            for number, fields in enumerate(reader, start=2):
                if len(fields) != len(header):
                    fail(f"{path}:{number}: expected {len(header)} fields, found {len(fields)}")
                try:
                    values = [float(f) if f != "" else None for f in fields]
                except ValueError as error:
                    fail(f"{path}:{number}: {error}")
                rows.append(dict(zip(header, values)))
    except OSError as error:
        fail(f"{path}: {error.strerror}")
    return params, rows


def plot(params, rows, out):
    figure, axes = plt.subplots(1, len(params), figsize=(4.5 * len(params), 3.6), squeeze=False)
    ok_rows = [r for r in rows if r["fitness"] is not None and math.isfinite(r["fitness"])]
    for axis, param in zip(axes[0], params):
        xs = [r[param] for r in ok_rows]
        ys = [r["fitness"] for r in ok_rows]
        low = [r["fitness"] - r["min_fitness"] for r in ok_rows]
        high = [r["max_fitness"] - r["fitness"] for r in ok_rows]
        axis.errorbar(xs, ys, yerr=[low, high], fmt="o", markersize=4, alpha=0.6, capsize=2, label="grid point")
        by_value = {}
        for x, y in zip(xs, ys):
            by_value.setdefault(x, []).append(y)
        values = sorted(by_value)
        axis.plot(values, [sum(by_value[v]) / len(by_value[v]) for v in values], "-", color="C3",
                  label="mean over the other parameters")
        axis.set_xlabel(param)
        axis.set_ylabel("fitness")
        axis.grid(True, alpha=0.3)
    axes[0][0].legend(fontsize="small")
    figure.suptitle(f"fitness across {len(rows)} grid points ({len(rows) - len(ok_rows)} without an ok run)")
    figure.tight_layout()
    figure.savefig(out, dpi=110)


def main():
    parser = argparse.ArgumentParser(description="Plot an orcs-batch sweep (DIR/sweep.csv).")
    parser.add_argument("folder", help="the sweep's output folder (orcs-batch sweep --out)")
    parser.add_argument("--out", help="the PNG to write (default DIR/sweep.png)")
    arguments = parser.parse_args()
    params, rows = read_sweep(os.path.join(arguments.folder, "sweep.csv"))
    out = arguments.out or os.path.join(arguments.folder, "sweep.png")
    plot(params, rows, out)
    print(f"plot_sweep.py: wrote {out}")


if __name__ == "__main__":
    main()
