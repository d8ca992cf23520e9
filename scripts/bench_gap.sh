#!/usr/bin/env bash
# Wall time of one full orcs-gap diagnosis of the A-Series example (docs/benchmarks.md, "The A-Series example"), at
# orcs-gap's default settings: a hidden 30 ms transport delay in the two 3 s A-Series identification motions, made
# on ODE (the exact engine, playing the measured robot) and diagnosed on MuJoCo among the whole catalogue, with
# each of BENCH_WORKERS local workers in turn. Prints a table row per worker count: time, replay jobs, the fitted
# delay with its 95 % interval, the held-out gap before and after, and the verdict's first words. Loopback only.
# Usage: scripts/bench_gap.sh [DELAY_S=0.03]
#   (GAP_OPTIONS: more orcs-gap options, e.g. --no-race or --generations 40; BENCH_WORKERS: default "2")
set -euo pipefail
cd "$(dirname "$0")/.."
delay=${1:-0.03}
gap=build/bin/orcs-gap
[ -x "$gap" ] || { echo "bench_gap: build first (scripts/build.sh)" >&2; exit 2; }
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
"$gap" synth --rig aseries --engine ODE --effect TransportDelay --set "/Effects/TransportDelay/Delay=$delay" \
  --motion scenarios/motions/aseries_identification_a.csv scenarios/motions/aseries_identification_b.csv \
  --out "$out/data" >/dev/null
echo "| workers | wall time (s) | replay jobs | fitted delay (ms, 95 %) | held-out gap (°) | verdict |"
echo "|---|---|---|---|---|---|"
for workers in ${BENCH_WORKERS:-2}; do
  start=$(date +%s%N)
  # shellcheck disable=SC2086  # GAP_OPTIONS is a list of options
  verdict=$("$gap" --rig aseries --engine MuJoCo --measured "$out/data/aseries_identification_a.csv" \
    --holdout "$out/data/aseries_identification_b.csv" --workers "$workers" ${GAP_OPTIONS:-} \
    --out "$out/report-$workers" 2>/dev/null | head -1)
  end=$(date +%s%N)
  figures=$(/usr/bin/python3 - "$out/report-$workers/report.json" <<'EOF'
import json, sys
r = json.load(open(sys.argv[1]))
delay = "—"
for c in r["candidates"]:
    if c["model"] == "TransportDelay":
        for p in c["parameters"]:
            if p["path"].endswith("/Delay"):
                delay = "%.1f ± %.1f" % (1000 * p["value"], 1000 * (p["ci95"] if p["ci95"] is not None else float("nan")))
v = r["verdict"]
print("%d | %s | %.3f → %.3f" % (r["cost"]["jobs"], delay, v["holdout_rms_refit"], v["holdout_rms_after"]))
EOF
)
  printf '| %s | %.1f | %s | %s |\n' "$workers" "$(( (end - start) / 1000000 ))e-3" "$figures" "${verdict:0:80}..."
done
