#!/usr/bin/env bash
# Wall time of one full orcs-gap diagnosis of the A-Series example (docs/benchmarks.md, "Gap diagnosis"):
# two A-Series runs (arm movement, waist bend; the first SECONDS of each) with a hidden 40 ms transport delay,
# diagnosed among all eight effects with 1 and then 2 local workers. Loopback only.
# Usage: scripts/bench_gap.sh [SECONDS=2] [GENERATIONS=3]
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-2}
generations=${2:-3}
gap=build/bin/orcs-gap
[ -x "$gap" ] || { echo "bench_gap: build first (scripts/build.sh)" >&2; exit 2; }
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
"$gap" synth --rig aseries --effect TransportDelay --set /Effects/TransportDelay/Delay=0.04 --duration "$seconds" \
  --motion scenarios/motions/arm_movement.csv scenarios/motions/waist_bend.csv --out "$out/data" >/dev/null
echo "| workers | wall time (s) | replay jobs | verdict |"
echo "|---|---|---|---|"
for workers in 1 2; do
  start=$(date +%s%N)
  verdict=$("$gap" --rig aseries --measured "$out/data/arm_movement.csv" --holdout "$out/data/waist_bend.csv" \
    --workers "$workers" --generations "$generations" --out "$out/report-$workers" 2>/dev/null | head -1)
  end=$(date +%s%N)
  jobs=$(/usr/bin/python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['cost']['jobs'])" \
    "$out/report-$workers/report.json")
  printf '| %s | %.1f | %s | %s |\n' "$workers" "$(( (end - start) / 1000000 ))e-3" "$jobs" "${verdict:0:60}..."
done
