#!/usr/bin/env bash
# Issue 47, "scale by simulation": 1,000 worker connections on one orcs-broker, on 127.0.0.1. The workers are
# lightweight echo workers (scripts/chaos/echo_workers.py: up to 250 DEALER connections per Python process, each
# saying READY, heartbeating every second and answering each job at once with its lease token); the driver is
# scripts/chaos/scale_bench.py. For each worker count (default 10 and 1000, a fresh broker each) it measures the
# time to connect, the broker's CPU and memory while idle (the cost of heartbeats), the round trip of a status
# request, the dispatch rate of trivial jobs and the broker's CPU per job, and the time from a batch's CANCEL
# until no worker is busy and until the last REVOKE arrived. docs/benchmarks.md, "1,000 worker connections",
# records the figures.
#
# Usage: scripts/bench_scale.sh [BIN] [--workers 10,1000] [--jobs 20000] [--credit 2] [--idle 10]
#   BIN   folder holding orcs-broker (default build/bin)
# Prints one JSON line per worker count and a Markdown table. Everything stops by itself (each wait is bounded).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
bin="$here/../build/bin"
if [ $# -gt 0 ] && [ "${1#--}" = "$1" ]; then bin=$1; shift; fi
[ -x "$bin/orcs-broker" ] || { echo "bench_scale.sh: no orcs-broker in $bin" >&2; exit 2; }
python=/usr/bin/python3
[ -x "$python" ] || python=python3
# 1,000 connections take 1,000 descriptors in the broker, and about as many in the echo processes together.
ulimit -n 8192 2>/dev/null || ulimit -n "$(ulimit -Hn)"
exec "$python" "$here/chaos/scale_bench.py" --bin "$bin" "$@"
