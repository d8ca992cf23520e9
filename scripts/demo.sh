#!/usr/bin/env bash
# Sets up, builds and runs orcs's main job on this machine: a batch of A-Series jobs — the evolution example's
# winning neural oscillator under 8 seeds of randomised motor and floor parameters — through the embedded broker
# and one local worker per core, every job recorded; then a summary of the fitness, a still of the best job drawn
# by orcs-view, and the command that opens the whole batch in a browser.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
scripts/build.sh

out=demo-out/batch
build/bin/orcs-batch run scenarios/evolution/rock_oscillator.json \
  --genome @scenarios/evolution/rock_oscillator.winner.json --jobs 8 --record all --out "$out"

# The fitness over the seeds (to stderr) and the best job (to stdout), from results.jsonl (one JSON object per job).
best=$(python3 -c '
import json, statistics, sys
jobs = [json.loads(line) for line in open(sys.argv[1]) if line.strip()]
ok = sorted((j for j in jobs if j["status"] == "ok"), key=lambda j: j["fitness"])
f = [j["fitness"] for j in ok]
print(f"demo: fitness over {len(f)} seeds: worst {f[0]:.3f}, median {statistics.median(f):.3f}, best {f[-1]:.3f}",
      file=sys.stderr)
print(ok[-1]["id"])
' "$out/results.jsonl")
build/bin/orcs-view --render "$out/recordings/$best.orcsrec" --out demo-out/best.png --width 960 --height 540

cat <<MESSAGE

demo: $(wc -l < "$out/results.jsonl") jobs in $out/results.jsonl; the best, $best, is drawn in demo-out/best.png.
demo: to watch every job in 3D, with plots of any joint, run
        build/bin/orcs-view $out
      and open the address it prints.
MESSAGE
