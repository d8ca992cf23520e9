#!/usr/bin/env bash
# The control loop of orcs-robot on emulated servos (docs/hardware.md, "The control loop"; docs/benchmarks.md):
# the A-Series' 21 AX-12+ behind the servo-bus emulator's pseudo-terminal, scenarios/motions/waist_bend.csv played
# at each rate; per rate the bus time of a period (a SYNC_WRITE of the goals + one READ of 8 bytes per servo) and
# how late the command went out, from the run's own log (/Robot/Cycle, /Robot/CommandDelay).
#
#   scripts/bench_robot.sh [--with-view] [RATES...]     # default: 50 100 200 Hz
#
# --with-view: each rate also with --view (the robot's model posed and recorded and the twin run and recorded each
# period, for orcs-view), right after the plain run: the cost of watching, against its peer in the same run.
#
# A pseudo-terminal has no baud rate: the figures are the program's and the operating system's share of a period.
set -euo pipefail
cd "$(dirname "$0")/.."
robot=build/bin/orcs-robot
[[ -x $robot ]] || { echo "bench_robot.sh: $robot is missing; run scripts/build.sh first" >&2; exit 2; }
views=(no)
if [[ ${1:-} == --with-view ]]; then views=(no yes); shift; fi
rates=("$@")
[[ ${#rates[@]} -gt 0 ]] || rates=(50 100 200)
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
echo "| rate (Hz) | --view | period (ms) | periods | bus time per period: median / p99 / max (ms) | command late: median / p99 (ms) | missed deadlines |"
echo "|---|---|---|---|---|---|---|"
for rate in "${rates[@]}"; do
for view in "${views[@]}"; do
  # A run stopped by its missed deadlines (exit 1) is a result too: the row says so.
  rc=0
  extra=()
  [[ $view == yes ]] && extra=(--view "$out/view_$rate")
  "$robot" --map scenarios/robots/aseries.joints.json --play scenarios/motions/waist_bend.csv --emulate --yes \
    --rate "$rate" --out "$out/run_$rate.csv" "${extra[@]}" 2>"$out/err_$rate.txt" || rc=$?
  [[ -s $out/run_$rate.csv ]] || { cat "$out/err_$rate.txt" >&2; exit 1; }
  [[ $rc -eq 0 ]] || echo "bench_robot.sh: at $rate Hz: $(grep -o 'stopped: [^;]*' "$out/err_$rate.txt")" >&2
  python3 - "$out/run_$rate.csv" "$rate" "$(grep -o '[0-9]* deadlines missed' "$out/err_$rate.txt" | cut -d' ' -f1)" "$view" <<'PY'
import csv, statistics, sys
path, rate, missed, view = sys.argv[1], float(sys.argv[2]), sys.argv[3], sys.argv[4]
lines = [l for l in open(path) if not l.startswith("#")]
columns = next(l for l in open(path) if l.startswith("# columns: "))[len("# columns: "):].strip().split(",")
rows = list(csv.reader(lines))
cycle = sorted(float(r[columns.index("/Robot/Cycle")]) * 1000 for r in rows)
late = sorted(float(r[columns.index("/Robot/CommandDelay")]) * 1000 for r in rows[:-1])
q = lambda v, p: v[min(len(v) - 1, int(p * len(v)))]
print(f"| {rate:g} | {view} | {1000 / rate:g} | {len(rows)} | {statistics.median(cycle):.2f} / {q(cycle, 0.99):.2f} / {cycle[-1]:.2f} "
      f"| {statistics.median(late):.3f} / {q(late, 0.99):.3f} | {missed} |")
PY
done
done
