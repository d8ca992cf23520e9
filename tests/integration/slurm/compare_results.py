#!/usr/bin/env python3
"""Checks that a batch run elsewhere gave the same bits as a reference batch of the same scenario and genome.

    compare_results.py REFERENCE/results.jsonl OTHER/results.jsonl --seeds N --workers W

OTHER must hold seeds 1..N once each, every job ok on W workers other than orcs-batch run's local ones, and each
job's fitness, terms and sets equal to the reference job of the same seed (and the same id when both batches have
N jobs). Floats print as their shortest round-trip form, so equal text is equal bits. Exits 1 naming the first
difference.
"""
import argparse
import json
import sys


def load(path):
    """The results of PATH by seed; no seed twice."""
    by_seed = {}
    with open(path) as lines:
        for number, line in enumerate(lines, 1):
            result = json.loads(line)
            if result["seed"] in by_seed:
                sys.exit(f"{path}:{number}: seed {result['seed']} twice")
            by_seed[result["seed"]] = result
    return by_seed


def first_difference(mine, theirs, path):
    """The path and both texts of the first place where MINE and THEIRS print differently, or None."""
    if isinstance(mine, dict) and isinstance(theirs, dict) and mine.keys() == theirs.keys():
        children = [(mine[k], theirs[k], f"{path}.{k}") for k in mine]
    elif isinstance(mine, list) and isinstance(theirs, list) and len(mine) == len(theirs):
        children = [(m, t, f"{path}[{i}]") for i, (m, t) in enumerate(zip(mine, theirs))]
    else:
        return None if json.dumps(mine) == json.dumps(theirs) else (path, json.dumps(mine), json.dumps(theirs))
    return next(filter(None, (first_difference(m, t, p) for m, t, p in children)), None)


def check_ok(result, where):
    if result["status"] != "ok" or not isinstance(result["fitness"], float):
        sys.exit(f"{where} {result['id']}: status {result['status']}, fitness {result['fitness']}: "
                 f"{result['message']}")


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("reference")
    parser.add_argument("other")
    parser.add_argument("--seeds", type=int, required=True)
    parser.add_argument("--workers", type=int, required=True)
    args = parser.parse_args()
    reference, other = load(args.reference), load(args.other)
    if sorted(other) != list(range(1, args.seeds + 1)):
        sys.exit(f"{args.other}: {len(other)} results; expected seeds 1..{args.seeds} once each")
    fields = ["fitness", "terms", "sets"] + (["id"] if len(reference) == len(other) else [])
    for seed, mine in sorted(other.items()):
        theirs = reference.get(seed)
        if theirs is None:
            sys.exit(f"{args.reference}: no result for seed {seed}")
        check_ok(mine, "other")
        check_ok(theirs, "reference")
        for field in fields:
            difference = first_difference(mine[field], theirs[field], field)
            if difference:
                sys.exit("seed {}: {} is {} here, {} in the reference".format(seed, *difference))
    ran_on = sorted({r["worker"] for r in other.values()})
    if any(w.startswith("local-") for w in ran_on) or len(ran_on) != args.workers:
        sys.exit(f"expected {args.workers} workers outside orcs-batch run; the jobs ran on {ran_on}")
    print(f"{args.seeds} results identical to the bit (fitness, terms, every set) on workers {', '.join(ran_on)}")


if __name__ == "__main__":
    main()
