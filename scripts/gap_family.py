#!/usr/bin/env python3
"""Runs a family of hidden-effect cases through orcs-gap and tabulates how often the hidden effect is named
(docs/gap.md, "How often it is right"). Each case is one `orcs-gap synth` with a hidden effect (its values, its
noise seed) and one diagnosis at default settings; the table counts each verdict as right (the hidden effect named
alone), a tie that holds it (named with a rival the runs cannot tell apart), wrong (another effect named alone, or a
tie without it), or none (nothing named).

    scripts/gap_family.py                                  # the whole family, scenarios/gap/family.json
    scripts/gap_family.py --only 'servo/LoadFriction'      # the cases whose name matches a regular expression
    scripts/gap_family.py --out build/gap-family --resume  # go on where an interrupted run stopped

Writes OUT/results.jsonl (one object per case, appended as each finishes), OUT/table.md (the table for
docs/gap.md) and each case's data and report under OUT/cases/<rig>/<name>/. Loopback only: every diagnosis
starts its own local workers. Python 3 standard library only.
"""
import argparse
import json
import math
import pathlib
import re
import shlex
import subprocess
import sys
import time

REPO = pathlib.Path(__file__).resolve().parent.parent
GAP = REPO / "build" / "bin" / "orcs-gap"
MOTIONS = REPO / "scenarios" / "motions"


def case_name(case):
    """<rig>/<effect or 'none'>-<values>: unique within a family."""
    if case.get("name"):
        return case["rig"] + "/" + case["name"]
    values = "-".join(f"{v:g}" if isinstance(v, (int, float)) else str(v) for v in case.get("set", {}).values())
    effect = "+".join(case.get("effects", [])) or "none"
    return f"{case['rig']}/{effect}-{values}" if values else f"{case['rig']}/{effect}"


def motions(rig, case, role):
    """The fit or held-out motions of a case: its own where it names them, else its rig's."""
    return case.get(role, rig[role])


def synth_command(rig, case, data):
    command = [str(GAP), "synth", *rig["rig"], "--engine", case.get("synth_engine", rig.get("synth_engine", "ODE")),
               "--seed", str(case["seed"]), "--out", str(data), "--motion"]
    command += [str(MOTIONS / (m + ".csv")) for m in motions(rig, case, "fit") + motions(rig, case, "holdout")]
    if rig.get("duration"):
        command += ["--duration", str(rig["duration"])]
    command += rig.get("synth_options", [])
    if rig.get("model"):
        command += ["--model", str(REPO / rig["model"])]
    for effect in case.get("effects", []):
        command += ["--effect", effect]
    for path, value in {**rig.get("set", {}), **case.get("set", {})}.items():
        command += ["--set", f"{path}={value}"]
    return command


def diagnose_command(rig, case, data, report, workers, extra):
    command = [str(GAP), *rig["rig"], "--engine", case.get("engine", rig.get("engine", "ODE")),
               "--measured", *[str(data / (m + ".csv")) for m in motions(rig, case, "fit")],
               "--holdout", *[str(data / (m + ".csv")) for m in motions(rig, case, "holdout")],
               "--workers", str(workers), "--out", str(report)]
    if rig.get("model"):
        command += ["--model", str(REPO / rig["model"])]
    return command + rig.get("options", []) + case.get("options", []) + extra


def classify(expected, named):
    """right / tie / wrong / none for the hidden effect(s) `expected` and the named ones."""
    if not named:
        return "none" if expected else "right"
    if not expected:
        return "wrong"
    if len(named) == 1:
        return "right" if named[0] in expected else "wrong"
    return "tie" if any(n in expected for n in named) else "wrong"


def run_case(rig, case, out, workers, extra):
    name = case_name(case)
    folder = out / "cases" / name
    data, report = folder / "data", folder / "report"
    started = time.monotonic()
    for command in (synth_command(rig, case, data), diagnose_command(rig, case, data, report, workers, extra)):
        done = subprocess.run(command, capture_output=True, text=True)
        (folder / "commands.txt").parent.mkdir(parents=True, exist_ok=True)
        with open(folder / "commands.txt", "a") as log:
            log.write(shlex.join(command) + "\n")
        if done.returncode != 0:
            return {"case": name, "outcome": "failed", "error": (done.stderr.strip().splitlines() or ["?"])[-1]}
    seconds = time.monotonic() - started
    result = json.loads((report / "report.json").read_text())
    verdict = result["verdict"]
    named = verdict.get("effects") or ([verdict["effect"]] if verdict.get("effect") else [])
    expected = case.get("expect", case.get("effects", []))
    fitted = {}
    for candidate in result["candidates"]:
        if candidate["model"] in named:
            # The effect's own parameters; LinkMass's is a link's mass, /Sim/<agent>/<link>/Mass.
            fitted[candidate["model"]] = {"/".join(v["path"].split("/")[-2 if v["path"].startswith("/Sim/") else -1:]):
                                          v["value"] for v in candidate["parameters"]
                                          if v["path"].startswith(("/Effects/", "/Sim/"))}
    before, after = verdict["holdout_rms_before"], verdict["holdout_rms_after"]
    return {
        "case": name, "rig": case["rig"], "hidden": case.get("set", {}), "seed": case["seed"],
        "engine": case.get("engine", rig.get("engine", "ODE")), "expected": expected, "named": named,
        "outcome": classify(expected, named), "holdout_before": before, "holdout_refit": verdict["holdout_rms_refit"],
        "holdout_after": after, "fitted": fitted,
        "verdict": verdict["text"], "seconds": round(seconds, 1), "jobs": result["cost"]["jobs"],
    }


def fmt_hidden(result):
    return ", ".join(f"{p.split('/')[-1]} {v:g}" if isinstance(v, (int, float)) else f"{p.split('/')[-1]} {v}"
                     for p, v in result.get("hidden", {}).items()) or "—"


def fmt_fitted(result):
    parts = []
    for effect, values in result.get("fitted", {}).items():
        parts.append(", ".join(f"{k} {v:.3g}" for k, v in values.items()))
    return "; ".join(p for p in parts if p) or "—"


NOISE_DEG = 0.189  # the angle sensor's noise in every family case (spec/aseries.md)


def above_noise(rms):
    """The part of a held-out RMS that the sensor noise does not explain (they add in quadrature)."""
    return math.sqrt(max(rms * rms - NOISE_DEG * NOISE_DEG, 0.0))


def halved(result):
    """Whether the named effect at least halved the held-out gap as given. The gap is what the noise does not explain:
    no model removes the sensor's noise, so a gap of 0.35° over a noise of 0.19° is halved at 0.23°, not at 0.175°."""
    return bool(result["named"]) and above_noise(result["holdout_after"]) <= 0.5 * above_noise(result["holdout_before"])


def visible(result):
    """Whether the hidden effect shows in the held-out run at all: its gap as given 10 % above the noise."""
    return result["holdout_before"] > 1.1 * NOISE_DEG


def table(results):
    """The markdown table of docs/gap.md, one row per case, then the hit rate per rig and effect."""
    lines = ["| case | hidden | seed | engine | named | outcome | held-out gap (°) | fitted | time (s) |",
             "|---|---|---|---|---|---|---|---|---|"]
    for r in results:
        if r["outcome"] == "failed":
            lines.append(f"| {r['case']} | | | | | **failed**: {r['error']} | | | |")
            continue
        gap = f"{r['holdout_before']:.3f} → {r['holdout_after']:.3f}"
        if r["named"] and r["holdout_after"] > 0.5 * r["holdout_before"]:
            gap += (f" (above the noise {above_noise(r['holdout_before']):.3f} → "
                    f"{above_noise(r['holdout_after']):.3f}{'' if halved(r) else ': not halved'})")
        if r["expected"] and not visible(r):
            gap += " (the held-out run does not show it: its gap is the noise)"
        outcome = r["outcome"] if r["outcome"] in ("right", "tie") else f"**{r['outcome']}**"
        lines.append(f"| {r['case']} | {fmt_hidden(r)} | {r['seed']} | {r['engine']} | "
                     f"{' or '.join(r['named']) or 'none'} | {outcome} | {gap} | {fmt_fitted(r)} | {r['seconds']:.0f} |")
    groups = {}
    for r in results:
        key = r["case"].split("-")[0]
        groups.setdefault(key, []).append(r)
    lines += ["", "| rig/effect | cases | named alone | in a tie | wrong | none | halved where named |",
              "|---|---|---|---|---|---|---|"]
    totals = {"cases": 0, "right": 0, "tie": 0, "wrong": 0, "none": 0, "failed": 0, "halved": 0, "named": 0}
    for key, rs in groups.items():
        count = {k: sum(1 for r in rs if r["outcome"] == k) for k in ("right", "tie", "wrong", "none", "failed")}
        named = [r for r in rs if r.get("named") and r["outcome"] in ("right", "tie")]
        halved_count = sum(1 for r in named if halved(r))
        lines.append(f"| {key} | {len(rs)} | {count['right']} | {count['tie']} | {count['wrong']} | "
                     f"{count['none'] + count['failed']} | {halved_count}/{len(named)} |")
        totals["cases"] += len(rs)
        for k in count:
            totals[k] += count[k]
        totals["halved"] += halved_count
        totals["named"] += len(named)
    n = max(totals["cases"], 1)
    lines.append(f"| **all** | {totals['cases']} | {totals['right']} | {totals['tie']} | {totals['wrong']} | "
                 f"{totals['none'] + totals['failed']} | {totals['halved']}/{totals['named']} |")
    lines += ["", f"Named right (alone or in a tie that holds it): {totals['right'] + totals['tie']} of "
              f"{totals['cases']} ({100.0 * (totals['right'] + totals['tie']) / n:.1f} %); alone: {totals['right']} "
              f"({100.0 * totals['right'] / n:.1f} %); wrong: {totals['wrong']}."]
    return "\n".join(lines) + "\n"


def main():
    global GAP
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--family", default=str(REPO / "scenarios" / "gap" / "family.json"))
    parser.add_argument("--only", default="", help="a regular expression: only the cases whose name it finds")
    parser.add_argument("--out", default=str(REPO / "build" / "gap-family"))
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--resume", action="store_true", help="skip the cases OUT/results.jsonl holds")
    parser.add_argument("--gap-options", default="", help="more orcs-gap options for every diagnosis")
    parser.add_argument("--list", action="store_true", help="list the cases and stop")
    parser.add_argument("--gap", default=str(GAP), help="the orcs-gap binary (default: build/bin/orcs-gap)")
    args = parser.parse_args()
    GAP = pathlib.Path(args.gap)
    if not GAP.exists():
        sys.exit(f"gap_family.py: {GAP} is missing; run scripts/build.sh first")
    family = json.loads(pathlib.Path(args.family).read_text())
    only = re.compile(args.only)
    cases = [c for c in family["cases"] if only.search(case_name(c))]
    names = [case_name(c) for c in family["cases"]]
    duplicates = {n for n in names if names.count(n) > 1}
    if duplicates:
        sys.exit(f"gap_family.py: {args.family}: cases named twice: {', '.join(sorted(duplicates))}")
    if args.list:
        print("\n".join(case_name(c) for c in cases))
        return
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    results_path = out / "results.jsonl"
    results = []
    if args.resume and results_path.exists():
        results = [json.loads(line) for line in results_path.read_text().splitlines() if line.strip()]
    elif results_path.exists():
        results_path.unlink()
    done = {r["case"] for r in results}
    extra = shlex.split(args.gap_options)
    todo = [c for c in cases if case_name(c) not in done]
    for i, case in enumerate(todo):
        print(f"gap_family.py: [{i + 1}/{len(todo)}] {case_name(case)}", file=sys.stderr, flush=True)
        result = run_case(family["rigs"][case["rig"]], case, out, args.workers, extra)
        results.append(result)
        with open(results_path, "a") as f:
            f.write(json.dumps(result) + "\n")
        print(f"gap_family.py:   {result['outcome']}: {result.get('verdict', result.get('error', ''))[:160]}",
              file=sys.stderr, flush=True)
        (out / "table.md").write_text(table(results))
    (out / "table.md").write_text(table(results))
    print(table(results))


if __name__ == "__main__":
    main()
