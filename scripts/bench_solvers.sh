#!/usr/bin/env bash
# How far ODE's iterative solver (dWorldQuickStep) moves the A-Series from the exact solver (dWorldStep, the
# original's) and how much faster it is: for (a) the robot standing 10 s and (b) the leg swing, runs orcs-sim
# once per solver with the same seed, logs the head position and the hip and knee joint angles, and reports the
# max and RMS deviation of every QuickStep trace from the dWorldStep trace, plus the wall time of the stepping
# (median of --repeat runs without logging, as orcs-sim reports it). Results: docs/benchmarks.md.
#
# Usage: scripts/bench_solvers.sh [--sim PATH] [--out DIR] [--iterations "20 50 ..."] [--repeat N]
#   --sim         orcs-sim to run (default: $ORCS_SIM, else build/bin/orcs-sim)
#   --out         where the traces, value files and summary.md go (default: build/bench-solvers)
#   --iterations  QuickStep iteration counts (default: "20 50 100 200")
#   --repeat      timing runs per case (default: 3)
#
# The command lines it runs, per case (SOLVER.val sets /Simulation/ODE/UseQuickStep=T and
# /Simulation/ODE/QuickStepIterations=N; dWorldStep runs without it):
#   standing:  orcs-sim --duration 10 --seed 0 [-val quickN.val] --log REGEX --out standing-SOLVER.csv
#   leg swing: orcs-sim -env scenarios/environments/leg_swing.xml -play Humanoid scenarios/motions/leg_swing.csv
#                       --duration D --seed 0 [-val quickN.val] --log REGEX --out leg_swing-SOLVER.csv
#   timing:    the same without --log/--out, --repeat times
# with REGEX = /Sim/Humanoid/Middle/Head/Position|/Sim/Humanoid/(Right|Left)/(HipRoll|HipPitch|HipYaw|Knee)/JointAngle
# The leg swing runs only when both scenario files exist and orcs-sim knows -play; otherwise the summary says it
# was skipped. D is the record's last keyframe time + 2 s, or ORCS_LEG_SWING_DURATION (seconds) when set.
#
# Joint angles are the logged JointAngle values, which carry the angle sensor's noise; every run uses seed 0 and
# draws the same noise, so the noise cancels in the differences. Exit status: 0 when every run was made (an
# unstable QuickStep run is a result, reported as such), 2 on bad arguments or a missing orcs-sim.
set -euo pipefail
cd "$(dirname "$0")/.."

sim="${ORCS_SIM:-build/bin/orcs-sim}"
out="build/bench-solvers"
iterations="20 50 100 200"
repeat=3
while [[ $# -gt 0 ]]; do
  case "$1" in
    --sim) sim="$2"; shift 2 ;;
    --out) out="$2"; shift 2 ;;
    --iterations) iterations="$2"; shift 2 ;;
    --repeat) repeat="$2"; shift 2 ;;
    -h|--help) sed -n '2,27p' "$0"; exit 0 ;;
    *) echo "bench_solvers.sh: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done
if [[ ! -x "$sim" ]]; then
  echo "bench_solvers.sh: orcs-sim not found at '$sim' (build it with scripts/build.sh, or pass --sim)" >&2
  exit 2
fi
mkdir -p "$out"

exec python3 - "$sim" "$out" "$iterations" "$repeat" <<'PYTHON'
import csv, math, os, re, statistics, subprocess, sys, time

sim, out, iterations, repeat = sys.argv[1], sys.argv[2], [int(n) for n in sys.argv[3].split()], int(sys.argv[4])
LOG = r"/Sim/Humanoid/Middle/Head/Position|/Sim/Humanoid/(Right|Left)/(HipRoll|HipPitch|HipYaw|Knee)/JointAngle"
HEAD = "/Sim/Humanoid/Middle/Head/Position"
LEG_ENV = "scenarios/environments/leg_swing.xml"
LEG_MOTION = "scenarios/motions/leg_swing.csv"

# Solvers: (label, value file or None).
solvers = [("dWorldStep", None)]
for n in iterations:
    path = os.path.join(out, f"quick{n}.val")
    with open(path, "w") as f:
        f.write(f"#ORCS Values\n/Simulation/ODE/UseQuickStep=T\n/Simulation/ODE/QuickStepIterations={n}\n")
    solvers.append((f"QuickStep {n}", path))

scenarios = [("standing", ["--duration", "10"])]
help_text = subprocess.run([sim, "--help"], capture_output=True, text=True).stdout
skipped = []
if os.path.exists(LEG_ENV) and os.path.exists(LEG_MOTION) and re.search(r"(^|\s)-+play\b", help_text):
    # The record's length plus 2 s to come to rest, unless ORCS_LEG_SWING_DURATION says otherwise.
    with open(LEG_MOTION) as f:
        rows = [line for line in f if line.strip() and not line.lstrip().startswith("#")]
    duration = os.environ.get("ORCS_LEG_SWING_DURATION") or f"{float(rows[-1].split(',')[0]) / 1000 + 2:g}"
    args = ["-env", LEG_ENV, "-play", "Humanoid", LEG_MOTION, "--duration", duration]
    scenarios.append(("leg_swing", args))
else:
    missing = [p for p in (LEG_ENV, LEG_MOTION) if not os.path.exists(p)]
    why = ("missing " + ", ".join(missing)) if missing else "this orcs-sim has no -play option"
    skipped.append(f"leg swing SKIPPED: {why} (merge main once the lead's leg swing has landed)")

SUMMARY = re.compile(r"simulated ([0-9.]+) s in (\d+) steps, wall time ([0-9.]+) s")

def run(args):
    """Runs orcs-sim; returns (exit code, simulated s, wall s of the stepping, stderr)."""
    p = subprocess.run([sim] + args, capture_output=True, text=True)
    m = SUMMARY.search(p.stdout)
    if p.returncode not in (0, 1) or not m:
        sys.exit(f"bench_solvers.sh: {' '.join([sim] + args)} failed ({p.returncode}): {p.stderr.strip()}")
    return p.returncode, float(m.group(1)), float(m.group(3)), p.stderr.strip()

def read_csv(path):
    with open(path) as f:
        lines = [line for line in f if not line.startswith("#") or line.startswith("# columns: ")]
    columns = lines[0][len("# columns: "):].strip().split(",")
    rows = [[float(x) for x in row] for row in csv.reader(lines[1:])]
    return columns, rows

def deviation(reference, trace):
    """Head distance (mm) and joint-angle difference (deg): max and RMS over the common time span."""
    columns, ref = reference
    columns2, rows = trace
    assert columns == columns2, "traces log different columns"
    head = [columns.index(HEAD + a) for a in (".x", ".y", ".z")]
    joints = [i for i, c in enumerate(columns) if c.endswith("/JointAngle")]
    n = min(len(ref), len(rows))
    head_d = [1e3 * math.dist([ref[k][i] for i in head], [rows[k][i] for i in head]) for k in range(n)]
    joint_d = [(abs(ref[k][i] - rows[k][i]), columns[i]) for k in range(n) for i in joints]
    worst = max(joint_d) if joint_d else (0.0, "")
    rms = lambda xs: math.sqrt(sum(x * x for x in xs) / len(xs)) if xs else 0.0
    return {"head_max": max(head_d), "head_rms": rms(head_d), "joint_max": worst[0],
            "joint_worst": worst[1].replace("/Sim/Humanoid/", "").replace("/JointAngle", ""),
            "joint_rms": rms([d for d, _ in joint_d]), "compared_s": ref[n - 1][0],
            "head_end": rows[n - 1][head[1]]}

lines = []
def say(text=""):
    print(text, flush=True)
    lines.append(text)

say(f"# Solver deviation: dWorldStep vs dWorldQuickStep ({time.strftime('%Y-%m-%d')}, {sim}, seed 0, "
    f"median wall time of {repeat} runs)")
for name, args in scenarios:
    say()
    say(f"## {name}: orcs-sim {' '.join(args)}")
    say()
    say("| solver | wall s (stepping) | steps/s | real-time factor | head max / RMS dev. (mm) | "
        "hip+knee angle max / RMS dev. (deg), worst joint | head height at end (m) | run |")
    say("|---|---|---|---|---|---|---|---|")
    reference = None
    for label, val in solvers:
        extra = ["-val", val] if val else []
        trace_path = os.path.join(out, f"{name}-{label.replace(' ', '')}.csv")
        code, simulated, _, message = run(args + ["--seed", "0"] + extra + ["--log", LOG, "--out", trace_path])
        timings = [run(args + ["--seed", "0"] + extra) for _ in range(repeat)]
        wall = statistics.median(t[2] for t in timings)
        steps = round(statistics.median(t[1] for t in timings) / 0.01)
        status = "ok" if code == 0 else message.replace("orcs-sim: ", "")
        trace = read_csv(trace_path)
        if reference is None:
            reference = trace
            d = deviation(reference, trace)
            dev = "— (reference) | —"
        else:
            d = deviation(reference, trace)
            span = "" if code == 0 else f" (over the first {d['compared_s']:g} s)"
            dev = (f"{d['head_max']:.1f} / {d['head_rms']:.1f}{span} | "
                   f"{d['joint_max']:.2f} / {d['joint_rms']:.2f}, {d['joint_worst']}")
        rate = steps / wall if wall > 0 else float("inf")
        say(f"| {label} | {wall:.3f} | {rate:,.0f} | {rate * 0.01:.1f} | {dev} | {d['head_end']:.4f} | {status} |")
for line in skipped:
    say()
    say(line)
with open(os.path.join(out, "summary.md"), "w") as f:
    f.write("\n".join(lines) + "\n")
print(f"\n(traces and summary.md in {out})")
PYTHON
