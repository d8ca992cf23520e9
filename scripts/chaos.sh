#!/usr/bin/env bash
# The chaos soak (issue 47; docs/reliability.md, "Chaos soak"): real orcs-broker, orcs-worker and orcs-batch
# processes — on 127.0.0.1, and (as root) in network namespaces of their own with CURVE — under a seeded schedule
# of faults, with the invariants checked throughout. The driver is scripts/chaos/chaos.py.
#
# Usage: scripts/chaos.sh --minutes N --seed S [--bin DIR] [--fault-interval SECONDS] [--no-netns]
#                         [--print-schedule] [--keep] [--verbose]
#   --bin DIR   the folder holding orcs-broker, orcs-worker, orcs-batch and orcs-keys (default build/bin)
# Prints the schedule (the same seed gives the same schedule) and a summary: minutes soaked, faults per kind, jobs,
# lost, duplicated, wedged seconds, broker memory. Exit 0 when every invariant held, 1 when one was violated,
# 2 when the soak could not be set up. Stops by itself; removes every namespace and process it made, also on
# failure or Ctrl-C.
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
bin="$here/../build/bin"
args=()
while [ $# -gt 0 ]; do
  case "$1" in
    --bin) bin=$2; shift 2 ;;
    --bin=*) bin=${1#--bin=}; shift ;;
    *) args+=("$1"); shift ;;
  esac
done
for program in orcs-broker orcs-worker orcs-batch orcs-keys; do
  [ -x "$bin/$program" ] || { echo "chaos.sh: no $program in $bin (build it, or give --bin DIR)" >&2; exit 2; }
done
python=/usr/bin/python3  # Debian's, which has python3-zmq and python3-protobuf (scripts/setup.sh)
[ -x "$python" ] || python=python3

prefix="ochaos$$"  # the namespaces' names start with this; nobody else's do
pidfile=$(mktemp /tmp/orcs-chaos-pids.XXXXXX)
cleanup() {
  # The driver stops everything itself; this is for a driver that died: its process groups (each program was
  # started in its own session; a pid is signalled only while it is still an orcs program), then its namespaces.
  local pid ns
  while read -r pid; do
    [ -n "$pid" ] && grep -qa orcs- "/proc/$pid/cmdline" 2>/dev/null && kill -KILL -- "-$pid" 2>/dev/null
  done <"$pidfile"
  rm -f "$pidfile"
  for ns in $(ip netns list 2>/dev/null | awk '{print $1}' | grep "^$prefix-"); do
    ip netns del "$ns" 2>/dev/null
  done
}
trap cleanup EXIT
trap 'exit 130' INT TERM

CHAOS_PIDFILE=$pidfile "$python" "$here/chaos/chaos.py" --bin "$bin" --netns-prefix "$prefix" ${args[@]+"${args[@]}"}
