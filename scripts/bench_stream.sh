#!/usr/bin/env bash
# Issue 18 item 5, "large batches stream": runs one batch of JOBS empty jobs (tests/bench/empty_job.json: one
# 0.01 s step of the pendulum rig) with `orcs-batch submit` against an `orcs-broker` and 2 local `orcs-worker`s,
# all on 127.0.0.1, and prints the peak memory (VmHWM, the high-water mark of the resident set) of the client and
# of the broker, and the wall time. docs/benchmarks.md, "Large batches", records its figures.
#
# Usage: scripts/bench_stream.sh [JOBS] [BIN]
#   JOBS  jobs in the batch (default 1000000)
#   BIN   folder holding orcs-batch, orcs-broker and orcs-worker (default build/bin; a build of main for the
#         "before" figure)
# Prints one line: jobs=N wall_s=S client_hwm_mb=C broker_hwm_mb=B results=R exit=E. Exit 0 when the batch ran
# completely (every job's line in results.jsonl, each id once).
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=${1:-1000000}
bin=$(realpath "${2:-build/bin}")
scenario=$(realpath tests/bench/empty_job.json)
work=$(mktemp -d /tmp/orcs-bench-stream.XXXXXX)
pids=()
cleanup() {
  for pid in "${pids[@]}"; do kill "$pid" 2>/dev/null || true; done
  wait 2>/dev/null || true
  rm -rf "$work"
}
trap cleanup EXIT

free_port() { python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'; }
client_port=$(free_port)
worker_port=$(free_port)
while [ "$worker_port" = "$client_port" ]; do worker_port=$(free_port); done

"$bin/orcs-broker" --client-port "$client_port" --worker-port "$worker_port" 2>"$work/broker.log" &
broker=$!
pids+=("$broker")
for i in 1 2; do
  "$bin/orcs-worker" --connect "tcp://127.0.0.1:$worker_port" --id "bench-$i" 2>"$work/worker-$i.log" &
  pids+=($!)
done
sleep 1  # the broker binds and the workers say READY

hwm_kb() { awk '/^VmHWM:/ {print $2}' "/proc/$1/status"; }
start=$(date +%s.%N)
set +e
/usr/bin/time -f '%M' -o "$work/client.maxrss" "$bin/orcs-batch" submit --broker "tcp://127.0.0.1:$client_port" \
  "$scenario" --jobs "$jobs" --out "$work/out" --quiet >"$work/client.out" 2>"$work/client.err"
status=$?
set -e
end=$(date +%s.%N)
broker_kb=$(hwm_kb "$broker")
client_kb=$(tail -n 1 "$work/client.maxrss")  # GNU time's %M: the client's maximum resident set, its VmHWM

results=0
unique=0
if [ -f "$work/out/results.jsonl" ]; then
  results=$(wc -l <"$work/out/results.jsonl")
  unique=$(python3 -c 'import json, sys; print(len({json.loads(l)["id"] for l in open(sys.argv[1])}))' \
    "$work/out/results.jsonl")
fi
sed 's/^/client: /' "$work/client.out" "$work/client.err" >&2
printf 'jobs=%s wall_s=%.1f client_hwm_mb=%.1f broker_hwm_mb=%.1f results=%s unique_ids=%s exit=%s\n' \
  "$jobs" "$(echo "$end - $start" | bc)" "$(echo "$client_kb / 1024" | bc -l)" "$(echo "$broker_kb / 1024" | bc -l)" \
  "$results" "$unique" "$status"
[ "$status" = 0 ] && [ "$results" = "$jobs" ] && [ "$unique" = "$jobs" ]
