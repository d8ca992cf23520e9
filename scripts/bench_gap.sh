#!/usr/bin/env bash
# Wall time of one full orcs-gap diagnosis of the A-Series example (docs/benchmarks.md, "The A-Series example"), at
# orcs-gap's default settings: a hidden 40 ms transport delay in two A-Series runs, the first SECONDS of the arm
# movement (fitted) and of the waist bend (held out), diagnosed among all nine effects with 1 and then 2 local
# workers. Loopback only.
# Usage: scripts/bench_gap.sh [SECONDS=2] [GENERATIONS] [HOLDOUT_SECONDS=SECONDS]
#   (GENERATIONS: orcs-gap's default, 40, unless given; GAP_OPTIONS: more orcs-gap options, e.g. --no-race,
#   --no-early-stop or --relax-scan; BENCH_WORKERS: the worker counts to time, default "1 2")
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-2}
generations=()
[ -n "${2:-}" ] && generations=(--generations "$2")
holdout_seconds=${3:-$seconds}
gap=build/bin/orcs-gap
[ -x "$gap" ] || { echo "bench_gap: build first (scripts/build.sh)" >&2; exit 2; }
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
hidden=(--rig aseries --effect TransportDelay --set /Effects/TransportDelay/Delay=0.04)
if [ "$holdout_seconds" = "$seconds" ]; then  # one synth: the runs draw noise seeds 1 and 2
  "$gap" synth "${hidden[@]}" --duration "$seconds" --motion scenarios/motions/arm_movement.csv \
    scenarios/motions/waist_bend.csv --out "$out/data" >/dev/null
else
  "$gap" synth "${hidden[@]}" --duration "$seconds" --motion scenarios/motions/arm_movement.csv --out "$out/data" >/dev/null
  "$gap" synth "${hidden[@]}" --duration "$holdout_seconds" --motion scenarios/motions/waist_bend.csv \
    --out "$out/data" >/dev/null
fi
echo "| workers | wall time (s) | replay jobs | stopped early | verdict |"
echo "|---|---|---|---|---|"
for workers in ${BENCH_WORKERS:-1 2}; do
  start=$(date +%s%N)
  verdict=$("$gap" --rig aseries --measured "$out/data/arm_movement.csv" --holdout "$out/data/waist_bend.csv" \
    --workers "$workers" "${generations[@]}" ${GAP_OPTIONS:-} --out "$out/report-$workers" 2>/dev/null | head -1)
  end=$(date +%s%N)
  cost=$(/usr/bin/python3 -c "import json,sys; c=json.load(open(sys.argv[1]))['cost']; \
print(c['jobs'], '|', c['jobs_stopped_early'])" "$out/report-$workers/report.json")
  printf '| %s | %.1f | %s | %s |\n' "$workers" "$(( (end - start) / 1000000 ))e-3" "$cost" "${verdict:0:90}..."
done
