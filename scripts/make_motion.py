#!/usr/bin/env python3
"""Turns a compact pose script (JSON) into a keyframe record in the raw layout (docs/formats.md, "Motion
scripts"). Python 3 standard library only.

    scripts/make_motion.py scenarios/motions/src/waist_bend.json scenarios/motions/waist_bend.csv
    scripts/make_motion.py --all        # every scenarios/motions/src/*.json -> scenarios/motions/*.csv
    scripts/make_motion.py --all --check  # fail if a committed record is out of date with its script

A script names the robot's motors (the A-Series by default), a row interval, a description and the command
that plays the record, and a list of poses in time order. A joint a pose names moves linearly to the pose's
angle, reaching it at the pose's `time_ms`, starting from the previous pose's time or `ramp_ms` earlier
(so ramps of different joints may overlap); "step": true jumps at `time_ms` instead. Rows are written every
`interval_ms` and at every ramp's start and end. Joints a pose does not name keep their value.
"Mirror/<joint>": a sets Right/<joint> = a and Left/<joint> = -a (a mirror move needs opposite signs,
spec/aseries.md §4c). Torques do not ramp: "torque" (a number for every motor, or {joint: value}) takes
effect at its pose's time.
"""
import argparse
import json
import pathlib
import sys

# The A-Series motors in input order with their ranges in degrees (spec/aseries.md §4c).
ASERIES_MOTORS = [
    ("Waist", 0, 150), ("Right/ShoulderYaw", -150, 150), ("Left/ShoulderYaw", -150, 150),
    ("Right/ShoulderPitch", -106.5, 94.5), ("Left/ShoulderPitch", -94.5, 106.5),
    ("Right/Elbow", -106.5, 87), ("Left/Elbow", -87, 106.5),
    ("Right/HipRoll", -45, 150), ("Left/HipRoll", -150, 45),
    ("Right/HipPitch", -75, 40), ("Left/HipPitch", -40, 75),
    ("Right/HipYaw", -15, 150), ("Left/HipYaw", -150, 15),
    ("Right/Knee", 0, 150), ("Left/Knee", -150, 0),
    ("Right/AnkleYaw", -81, 29.5), ("Left/AnkleYaw", -29.5, 81),
    ("Right/AnklePitch", -66.5, 55), ("Left/AnklePitch", -55, 66.5),
    ("Head/Pan", -135, 135), ("Head/Tilt", -95, 150),
]
PENDULUM_MOTORS = [("Motor", -150, 150)]
ROBOTS = {"ASeries": ASERIES_MOTORS, "Pendulum": PENDULUM_MOTORS}
DEFAULT_TORQUE = 0.586810005  # the motors' default DesiredTorque (spec §4d)
REPO = pathlib.Path(__file__).resolve().parent.parent


class ScriptError(Exception):
    pass


def expand(name, value, known, negate_left):
    """[(motor, value)] for one key of a pose; "Mirror/X" names both sides."""
    if name.startswith("Mirror/"):
        joint = name[len("Mirror/"):]
        pairs = [("Right/" + joint, value), ("Left/" + joint, -value if negate_left else value)]
    else:
        pairs = [(name, value)]
    for motor, _ in pairs:
        if motor not in known:
            raise ScriptError(f"unknown joint {motor!r} (known: {', '.join(known)})")
    return pairs


def number(value, what):
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ScriptError(f"{what}: expected a number, found {value!r}")
    return float(value)


def make_rows(script):
    """[(time_ms, [angle, torque] per motor)] from a parsed script, and the motor table."""
    motors = ROBOTS.get(script.get("robot", "ASeries"))
    if motors is None:
        raise ScriptError(f"robot: expected one of {sorted(ROBOTS)}, found {script.get('robot')!r}")
    index = {name: i for i, (name, _, _) in enumerate(motors)}
    interval = number(script.get("interval_ms", 50), "interval_ms")
    if interval <= 0:
        raise ScriptError("interval_ms: expected a positive number")
    poses = script.get("poses")
    if not isinstance(poses, list) or not poses:
        raise ScriptError("poses: expected a non-empty list")

    # Per motor: ramps (start, end, from, to), in time order; torque changes (time, value).
    ramps = [[] for _ in motors]
    torques = [[(0.0, DEFAULT_TORQUE)] for _ in motors]
    held = [0.0] * len(motors)  # each motor's angle after its last ramp (initially 0)
    times = {0.0}
    previous = 0.0
    for p, pose in enumerate(poses):
        where = f"pose {p + 1}"
        time = number(pose.get("time_ms"), where + " time_ms")
        if time < previous:
            raise ScriptError(f"{where}: time_ms {time:g} is earlier than the pose before ({previous:g})")
        ramp = 0.0 if pose.get("step", False) else number(pose.get("ramp_ms", time - previous), where + " ramp_ms")
        if not 0 <= ramp <= time:
            raise ScriptError(f"{where}: ramp_ms {ramp:g} is negative or starts before 0")
        times.update((time - ramp, time))
        previous = time
        for key, value in pose.items():
            if key in ("time_ms", "step", "ramp_ms", "note"):
                continue
            if key == "torque":
                items = value.items() if isinstance(value, dict) else [(name, value) for name, _, _ in motors]
                for name, torque in items:
                    for motor, t in expand(name, number(torque, f"{where} torque"), index, False):
                        if not -1 <= t <= 1:
                            raise ScriptError(f"{where}: torque {t:g} of {motor} is outside -1...1")
                        torques[index[motor]].append((time, t))
                continue
            for motor, angle in expand(key, number(value, f"{where} {key}"), index, True):
                m = index[motor]
                _, low, high = motors[m]
                if not low <= angle <= high:
                    raise ScriptError(f"{where}: {motor} {angle:g} is outside its range {low:g}...{high:g}")
                if ramps[m] and time - ramp < ramps[m][-1][1]:
                    raise ScriptError(f"{where}: the ramp of {motor} starts before its previous one ends")
                ramps[m].append((time - ramp, time, held[m], angle))
                held[m] = angle

    def angle_at(m, t):
        value = 0.0
        for start, end, a, b in ramps[m]:
            if t < start:
                break
            value = b if t >= end else a + (b - a) * (t - start) / (end - start)
        return value

    def torque_at(m, t):
        return [value for when, value in torques[m] if when <= t][-1]

    times.update(n * interval for n in range(int(previous // interval) + 1))
    rows = [(t, [v for m in range(len(motors)) for v in (angle_at(m, t), torque_at(m, t))])
            for t in sorted(times)]
    # A row equal to the one before changes nothing (values hold between rows); keep the last for the duration.
    return [r for i, r in enumerate(rows) if i in (0, len(rows) - 1) or r[1] != rows[i - 1][1]], motors


def fmt(value, decimals=3):
    text = f"{value:.{decimals}f}".rstrip("0").rstrip(".")
    return "0" if text == "-0" else text


def render(source):
    """The record text a pose script generates."""
    try:
        script = json.loads(pathlib.Path(source).read_text())
        rows, motors = make_rows(script)
    except (OSError, json.JSONDecodeError, ScriptError, AttributeError, TypeError) as error:
        raise SystemExit(f"make_motion: {source}: {error}")
    try:
        source_name = pathlib.Path(source).resolve().relative_to(REPO)
    except ValueError:
        source_name = pathlib.Path(source)
    description = script.get("description", [])
    lines = [f"# {line}".rstrip() for line in ([description] if isinstance(description, str) else description)]
    if "play" in script:
        lines.append(f"# play: {script['play']}")
    lines.append(f"# generated by scripts/make_motion.py from {source_name}; edit that file, not this one")
    lines.append("# columns: time_ms, " + ", ".join(f"{name} angle, {name} torque" for name, _, _ in motors))
    lines.append("# layout: raw")
    # Angles to 0.001 degrees; torques exactly enough to keep the default 0.586810005.
    lines += [",".join([fmt(t)] + [fmt(v, 3 + 6 * (i % 2)) for i, v in enumerate(values)]) for t, values in rows]
    return "\n".join(lines) + "\n"


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("source", nargs="?", help="pose script (.json)")
    parser.add_argument("target", nargs="?", help="record to write (.csv)")
    parser.add_argument("--all", action="store_true", help="regenerate every scenarios/motions/src/*.json")
    parser.add_argument("--check", action="store_true",
                        help="with --all: write nothing, fail if a record differs from what its script gives")
    args = parser.parse_args()
    if args.all:
        stale = []
        for source in sorted((REPO / "scenarios/motions/src").glob("*.json")):
            target = REPO / "scenarios/motions" / (source.stem + ".csv")
            text = render(source)
            if args.check:
                if not target.exists() or target.read_text() != text:
                    stale.append(str(target.relative_to(REPO)))
            else:
                target.write_text(text)
        if stale:
            print("make_motion: out of date with its script (run scripts/make_motion.py --all): " + ", ".join(stale))
            return 1
    elif args.source and args.target and not args.check:
        pathlib.Path(args.target).write_text(render(args.source))
    else:
        parser.error("give SOURCE and TARGET, or --all [--check]")
    return 0


if __name__ == "__main__":
    sys.exit(main())
