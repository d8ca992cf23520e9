#!/usr/bin/env bash
# What orcs-osp -gui costs an OSP client (docs/benchmarks.md, "orcs-osp -gui"): the wall time of the example OSP
# client's steps against orcs-osp and against orcs-osp -gui (orcs-view's live session publishing every step), the
# two alternating in one run so that both see the same machine. Loopback only; each server ends with its round.
#
#   scripts/bench_osp_gui.sh [ROUNDS=3] [STEPS=2000]      (after scripts/build.sh)
set -euo pipefail
cd "$(dirname "$0")/.."
rounds=${1:-3}
steps=${2:-2000}
out=$(mktemp)
trap 'rm -f "$out"' EXIT
for round in $(seq 1 "$rounds"); do
  for mode in orcs-osp orcs-osp-gui; do
    args=(-port 0 -odcp_port 0)
    [ "$mode" = orcs-osp-gui ] && args+=(-gui --view-port 0)
    build/bin/orcs-osp "${args[@]}" > "$out" 2> /dev/null &
    server=$!
    for _ in $(seq 1 200); do grep -q ' osp=' "$out" && break; sleep 0.05; done
    port=$(grep -oP ' osp=127\.0\.0\.1:\K[0-9]+' "$out")
    start=$(date +%s.%N)
    python3 scripts/osp_example_client.py --port "$port" --steps "$steps" > /dev/null
    end=$(date +%s.%N)
    kill "$server"
    wait "$server" 2> /dev/null || true
    python3 -c "import sys; s = float(sys.argv[2]) - float(sys.argv[1]); print(f'round {sys.argv[3]}, {sys.argv[4]}: {s:.2f} s, {1000 * s / int(sys.argv[5]):.3f} ms a step')" \
      "$start" "$end" "$round" "$mode" "$steps"
  done
done
echo "load: $(cut -d' ' -f1-3 /proc/loadavg)"
