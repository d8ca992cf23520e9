#!/usr/bin/env python3
"""Turns the XL330 pendulum CSVs of scenarios/data/xl330-pendulum back into BAM's JSON logs (the format they were
converted from: radians, one object with the rig's constants and `entries`), so that orcs-gap's BAM reader can be
checked against the CSV reader on the same runs (docs/gap_measured_data.md, "BAM's JSON logs").

    scripts/xl330_to_bam.py scenarios/data/xl330-pendulum/*.csv --out build/xl330-bam

Writes OUT/<name>.json per CSV. Python 3 standard library only.
"""
import argparse
import csv
import json
import math
import pathlib
import sys

RIG_KEYS = {"motor": ("motor", str), "load_mass_kg": ("mass", float), "load_distance_m": ("length", float),
            "firmware_kp": ("kp", float), "supply_v": ("vin", float), "dt_s": ("dt", float),
            "trajectory": ("trajectory", str)}


def rig_of(comment):
    """The rig's constants from the CSV's first line, '# XL330 pendulum log: key=value ...'."""
    rig = {}
    for token in comment.split():
        key, _, value = token.partition("=")
        if key in RIG_KEYS and value:
            name, kind = RIG_KEYS[key]
            rig[name] = kind(value)
    return rig


def convert(path):
    with open(path, newline="") as f:
        comment = f.readline()
        if not comment.startswith("#"):
            sys.exit(f"xl330_to_bam.py: {path}:1: expected the rig's comment line, found {comment.strip()!r}")
        log = rig_of(comment)
        log["entries"] = [{"timestamp": float(row["time_s"]),
                           "position": math.radians(float(row["position_deg"])),
                           "speed": math.radians(float(row["speed_deg_s"])),
                           "load": float(row["load"]),
                           "input_volts": float(row["input_volts"]),
                           "temp": float(row["temperature_c"]),
                           "goal_position": math.radians(float(row["goal_deg"])),
                           "torque_enable": row["torque_enable"].strip() == "1"}
                          for row in csv.DictReader(f)]
    return log


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("csv", nargs="+", help="XL330 CSV logs")
    parser.add_argument("--out", required=True, help="folder for the JSON logs")
    args = parser.parse_args()
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    for path in args.csv:
        target = out / (pathlib.Path(path).stem + ".json")
        target.write_text(json.dumps(convert(path)))
        print(f"xl330_to_bam.py: {path} → {target}", file=sys.stderr)


if __name__ == "__main__":
    main()
