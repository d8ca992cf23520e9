#!/usr/bin/python3
"""How evolved controllers fare on parameter sets they never met, beside how their searches went.

    scripts/plot_generalisation.py --run LABEL FITNESS_CSV RESULTS_JSONL [--run ...] [--term sway] [--unit m]
                                   [--title TEXT] --out FIG.png

Each --run is one evolution: its fitness.csv (orcs-batch evolve's, per generation) and a results.jsonl of its
winner run on unseen seeds (orcs-batch run SCENARIO --genome @WINNER --seed S --jobs N, docs/evolution.md). Left:
the best fitness so far per generation of each search. Right: the chosen term in every parameter set of the
unseen runs, one point per set, with a red cross on each set in which the robot fell (its term "falls" > 0); the
legend counts them. Bad input exits 2 with one line naming the file and line. Needs matplotlib (Debian's
python3-matplotlib).
"""
import argparse
import csv
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402 (after choosing the headless backend)
from matplotlib.ticker import MaxNLocator  # noqa: E402

COLOURS = ["tab:blue", "tab:orange", "tab:green", "tab:purple"]


def fail(message):
    print(f"plot_generalisation.py: {message}", file=sys.stderr)
    sys.exit(2)


def read_search(path):
    """(generations, best fitness so far) of an orcs-batch evolve fitness.csv."""
    generations, best = [], []
    try:
        with open(path, newline="") as handle:
            for line, row in enumerate(csv.DictReader(handle), start=2):
                try:
                    generations.append(int(row["generation"]))
                    best.append(float(row["best_so_far"]) if row["best_so_far"] else float("nan"))
                except (KeyError, TypeError, ValueError):
                    fail(f"{path}:{line}: expected a generation and best_so_far, as orcs-batch evolve writes them")
    except OSError as error:
        fail(f"{path}: {error.strerror}")
    if not generations:
        fail(f"{path}: no generation")
    return generations, best


def read_sets(path, term):
    """Per parameter set of every job of a results.jsonl: (the term's value, whether the robot fell)."""
    sets = []
    try:
        with open(path) as handle:
            for line, text in enumerate(handle, start=1):
                try:
                    result = json.loads(text)
                    for one in result["sets"]:
                        terms = one["terms"]
                        sets.append((float(terms[term]), float(terms.get("falls", 0)) > 0))
                except json.JSONDecodeError:
                    fail(f"{path}:{line}: not a JSON line")
                except (KeyError, TypeError, ValueError):
                    fail(f"{path}:{line}: expected \"sets\" whose \"terms\" hold '{term}' (orcs-batch run's results)")
    except OSError as error:
        fail(f"{path}: {error.strerror}")
    if not sets:
        fail(f"{path}: no parameter set")
    return sets


def build_figure(runs, term, unit, title):
    """runs: [(label, (generations, best so far), [(value, fell), ...]), ...]."""
    figure, (search, unseen) = plt.subplots(1, 2, figsize=(12, 5.2))
    fall_labelled = False
    for index, (label, (generations, best), sets) in enumerate(runs):
        colour = COLOURS[index % len(COLOURS)]
        search.plot(generations, best, marker="o", markersize=3, color=colour, label=label)
        # The sets side by side around the run's place on the x axis, so that equal values stay visible.
        positions = [index + 1 + 0.3 * ((k % 12) / 11 - 0.5) for k in range(len(sets))]
        falls = sum(1 for _, fell in sets if fell)
        unseen.scatter(positions, [value for value, _ in sets], s=14, color=colour,
                       label=f"{label}: {len(sets)} sets, {falls} with a fall")
        fell = [(p, value) for p, (value, f) in zip(positions, sets) if f]
        if fell:
            unseen.scatter([p for p, _ in fell], [v for _, v in fell], marker="x", s=40, color="red",
                           label=None if fall_labelled else "a set with a fall")
            fall_labelled = True
    search.set_title("the search: best fitness so far\n(on the parameter sets it was scored on)")
    search.set_xlabel("generation")
    search.set_ylabel("fitness (higher is better)")
    search.xaxis.set_major_locator(MaxNLocator(integer=True))
    search.grid(alpha=0.3)
    search.legend(loc="upper center", bbox_to_anchor=(0.5, -0.13), frameon=False)
    unseen.set_title("the winner on unseen parameter sets\n(one point per set)")
    unseen.set_xticks(range(1, len(runs) + 1), [label for label, _, _ in runs])
    unseen.set_xlim(0.5, len(runs) + 0.5)
    unseen.set_ylabel(f"{term} ({unit}, higher is better)")
    unseen.grid(alpha=0.3, axis="y")
    unseen.legend(loc="upper center", bbox_to_anchor=(0.5, -0.08), frameon=False)
    figure.suptitle(title)
    figure.tight_layout()
    return figure


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--run", nargs=3, action="append", required=True, metavar=("LABEL", "FITNESS_CSV", "RESULTS"))
    parser.add_argument("--term", default="sway", help="the fitness term shown per set (default sway)")
    parser.add_argument("--unit", default="m", help="the term's unit, for the axis label (default m)")
    parser.add_argument("--title", default="Evolved on the same or on fresh parameter sets")
    parser.add_argument("--out", required=True, help="the picture (PNG)")
    args = parser.parse_args(argv)
    runs = [(label, read_search(fitness), read_sets(results, args.term)) for label, fitness, results in args.run]
    figure = build_figure(runs, args.term, args.unit, args.title)
    figure.savefig(args.out, dpi=100)
    plt.close(figure)
    print(f"plot_generalisation.py: wrote {args.out}")


if __name__ == "__main__":
    main()
