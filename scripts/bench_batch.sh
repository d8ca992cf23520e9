#!/usr/bin/env bash
# Batch evaluation benchmarks, side by side in one run (issue 4; docs/benchmarks.md, "Batch evaluation"):
#   1. dispatch  the broker's rate for empty jobs at default settings: the Google Benchmark
#                BM_BrokerDispatchEmptyJobs (a real Broker, BatchClient and two echo WorkerConnections over TCP
#                on 127.0.0.1), plus the same with the credit fixed at 2 for reference
#   2. dask      the same number of empty tasks through Dask distributed: scripts/bench_dask.py, a LocalCluster
#                on 127.0.0.1 with 2 worker processes (Debian's python3-distributed, run with /usr/bin/python3)
#   3. scaling   a real A-Series batch (--jobs N of --scenario) with `orcs-batch run` on 1 and on 2 workers:
#                wall time of the whole command, and the ratio
#   4. parallel  the same batch as one `orcs-sim --scenario` process per job under GNU parallel, 2 at a time
#   5. memory    orcs-worker's peak resident memory (VmHWM of /proc/PID/status, read when the batch is done)
#                while two orcs-worker processes serve the same batch from an orcs-broker process
# Runs 3 and 4 alternate within each repetition, so that load from elsewhere falls on every variant alike; the
# load average is read before and after each. Everything listens on 127.0.0.1 only. Builds nothing: expects a
# build directory made by `scripts/build.sh -DORCS_BUILD_BENCHMARKS=ON`. Installs GNU parallel and
# python3-distributed with apt-get (sudo when not root) when they are missing.
#
# Usage: scripts/bench_batch.sh [BUILD_DIR | --build DIR] [--scenario FILE] [--jobs N] [--repeat R]
#                               [--wait-quiet MINUTES] [--write-docs]
#   BUILD_DIR     default build
#   --scenario    default scenarios/examples/swing_oscillator.json
#   --jobs        real jobs per batch (default 40; seeds 1..N)
#   --repeat      repetitions of every measurement (default 3); the tables give medians
#   --wait-quiet  before each real-batch run, wait up to MINUTES (default 0: not at all) for other processes to
#                 take less than 0.15 cores over 2 s; the notes give what they took during every run regardless
#   --write-docs  also rewrite the figures of docs/benchmarks.md, "Batch evaluation"
set -euo pipefail
cd "$(dirname "$0")/.."

die() {
  echo "bench_batch: $*" >&2
  exit 2
}

invocation="scripts/bench_batch.sh $*" # recorded with the figures
build=build
scenario=scenarios/examples/swing_oscillator.json
jobs=40
repeat=3
write_docs=0
quiet_wait=0
empty_jobs=10000 # BM_BrokerDispatchEmptyJobs's batch size; Dask gets the same number of tasks
while [ $# -gt 0 ]; do
  case "$1" in
    --build) build=${2:?--build needs a directory}; shift 2 ;;
    --scenario) scenario=${2:?--scenario needs a file}; shift 2 ;;
    --jobs) jobs=${2:?--jobs needs a number}; shift 2 ;;
    --repeat) repeat=${2:?--repeat needs a number}; shift 2 ;;
    --wait-quiet) quiet_wait=${2:?--wait-quiet needs minutes}; shift 2 ;;
    --write-docs) write_docs=1; shift ;;
    -h | --help) sed -n '2,/^set -euo/p' "$0" | sed '$d' | sed 's/^# \{0,1\}//'; exit 0 ;;
    -*) die "unknown option $1 (see --help)" ;;
    *) build=$1; shift ;;
  esac
done
[[ "$jobs" =~ ^[1-9][0-9]*$ ]] || die "--jobs must be a positive integer, got '$jobs'"
[[ "$repeat" =~ ^[1-9][0-9]*$ ]] || die "--repeat must be a positive integer, got '$repeat'"
[[ "$quiet_wait" =~ ^[0-9]+$ ]] || die "--wait-quiet must be a whole number of minutes, got '$quiet_wait'"
[ -f "$scenario" ] || die "no scenario file $scenario"
for program in bin/orcs-batch bin/orcs-worker bin/orcs-broker bin/orcs-sim; do
  [ -x "$build/$program" ] || die "no $build/$program: run scripts/build.sh first (or give the build directory)"
done
dispatch_bench=$build/tests/bench/broker_dispatch_bench
[ -x "$dispatch_bench" ] || die "no $dispatch_bench: build with scripts/build.sh -DORCS_BUILD_BENCHMARKS=ON"
py=/usr/bin/python3 # Debian's python: the one with Debian's modules (python3-distributed)
[ -x "$py" ] || die "no $py"
[ -x /usr/bin/time ] || die "no /usr/bin/time (Debian package time)"

# --- the peers' packages ------------------------------------------------------------------------------------
missing=()
for p in parallel python3-distributed; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "bench_batch: installing ${missing[*]}" >&2
  sudo_cmd=()
  [ "$(id -u)" -ne 0 ] && sudo_cmd=(sudo)
  export DEBIAN_FRONTEND=noninteractive
  "${sudo_cmd[@]}" apt-get update -qq
  "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
parallel_bin=/usr/bin/parallel
"$parallel_bin" --version 2>/dev/null | head -1 | grep -q "GNU parallel" ||
  die "$parallel_bin is not GNU parallel (moreutils has one of the same name)"
"$py" -c 'import distributed' 2>/dev/null || die "$py cannot import distributed (python3-distributed)"

# --- helpers ------------------------------------------------------------------------------------------------
work=$(mktemp -d /tmp/bench_batch.XXXXXX)
started=() # PIDs of the processes this script started in the background
cleanup() {
  for pid in "${started[@]}"; do kill -TERM "$pid" 2>/dev/null || true; done
  for pid in "${started[@]}"; do wait "$pid" 2>/dev/null || true; done
  rm -rf "$work"
}
trap cleanup EXIT
trap 'exit 130' INT TERM

now() { date +%s.%N; }
load() { cut -d' ' -f1 /proc/loadavg; }
clk_tck=$(getconf CLK_TCK)
# CPU seconds the machine spent busy so far (user, nice, system, irq, softirq, and steal: time the hypervisor gave
# to others), from /proc/stat.
busy_seconds() { awk -v hz="$clk_tck" '/^cpu / { printf "%.2f\n", ($2 + $3 + $4 + $7 + $8 + $9) / hz }' /proc/stat; }
# median/min/max of numbers on stdin, printed as "median min max" with %.{$1}f
stats() { "$py" -c '
import statistics, sys
v = [float(x) for x in sys.stdin.read().split()]
f = "%%.%sf" % sys.argv[1]
print(" ".join(f % x for x in (statistics.median(v), min(v), max(v))))' "$1"; }
timed() { # $1: file for the wall seconds; $2: what, for the foreign-CPU note; the rest: the command
  local out=$1 what=$2 start end b0 b1 status=0
  shift 2
  b0=$(busy_seconds)
  start=$(now)
  /usr/bin/time -f "%U %S" -o "$work/own-cpu" "$@" || status=$?
  end=$(now)
  b1=$(busy_seconds)
  awk -v s="$start" -v e="$end" 'BEGIN { printf "%.3f\n", e - s }' >>"$out"
  # CPU the machine spent beyond the command's own (its children's included), as cores over the wall time.
  foreign+=("$what: $(tail -1 "$work/own-cpu" | awk -v b0="$b0" -v b1="$b1" -v s="$start" -v e="$end" \
    '{ f = (b1 - b0 - $1 - $2) / (e - s); printf "%.2f", f < 0 ? 0 : f }')")
  return $status
}
# Waits, at most --wait-quiet minutes, until other processes take less than 0.15 cores over a 2 s sample.
wait_quiet() {
  [ "$quiet_wait" -gt 0 ] || return 0
  local deadline=$((SECONDS + 60 * quiet_wait)) b0 b1
  while [ $SECONDS -lt $deadline ]; do
    b0=$(busy_seconds)
    sleep 2 # the sampling window: CPU use is only defined over an interval
    b1=$(busy_seconds)
    awk -v a="$b0" -v b="$b1" 'BEGIN { exit !((b - a) / 2 < 0.15) }' && return 0
  done
  echo "bench_batch: other processes still busy after $quiet_wait min; measuring anyway (see the notes)" >&2
}
count_ok() { grep -c '"status":"ok"' "$1" || true; }
loads=()   # "what: before→after" load averages
foreign=() # "what: N" cores' worth of CPU that other processes took during the measurement

echo "bench_batch: $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg) at the start" >&2

# --- 1. dispatch rate of empty jobs -------------------------------------------------------------------------
run_dispatch() { # $1: benchmark argument suffix, e.g. 2/16/0 (no CURVE) → items/s of each repetition, one per line
  timed "$work/tdisp" "dispatch $1" "$dispatch_bench" --benchmark_filter="BM_BrokerDispatchEmptyJobs/$empty_jobs/$1/" \
    --benchmark_repetitions="$repeat" --benchmark_format=json >"$work/dispatch.json" 2>/dev/null ||
    die "$dispatch_bench failed"
  "$py" -c '
import json, sys
for b in json.load(sys.stdin)["benchmarks"]:
    if b.get("run_type") == "iteration":
        print(b["items_per_second"])' <"$work/dispatch.json"
}
echo "bench_batch: dispatch rate, $empty_jobs empty jobs, default settings (x$repeat)" >&2
l0=$(load)
run_dispatch 2/16/0 >"$work/dispatch-default" # not in a subshell: timed records the foreign CPU
read -r dispatch_default dispatch_default_min dispatch_default_max < <(stats 0 <"$work/dispatch-default")
echo "bench_batch: dispatch rate, credit fixed at 2 (x$repeat)" >&2
run_dispatch 2/2/0 >"$work/dispatch-fixed"
read -r dispatch_fixed dispatch_fixed_min dispatch_fixed_max < <(stats 0 <"$work/dispatch-fixed")
loads+=("dispatch: $l0→$(load)")

# --- 2. Dask ------------------------------------------------------------------------------------------------
echo "bench_batch: Dask distributed, $empty_jobs empty tasks, 2 worker processes (x$repeat)" >&2
l0=$(load)
timed "$work/td" "dask" "$py" scripts/bench_dask.py --tasks "$empty_jobs" --workers 2 --repeat "$repeat" \
  >"$work/dask.txt" 2>"$work/dask.err" ||
  { cat "$work/dask.err" >&2; die "scripts/bench_dask.py failed"; }
loads+=("dask: $l0→$(load)")
dask_line=$(tail -1 "$work/dask.txt")
dask_rate=$(sed -n 's/.* median=\([0-9.]*\) .*/\1/p' <<<"$dask_line")
dask_min=$(sed -n 's/.* min=\([0-9.]*\) .*/\1/p' <<<"$dask_line")
dask_max=$(sed -n 's/.* max=\([0-9.]*\) .*/\1/p' <<<"$dask_line")
dask_version=$(sed -n 's/.* dask=\([^ ]*\).*/\1/p' <<<"$dask_line")
[ -n "$dask_rate" ] || die "no rate in bench_dask.py's output: $dask_line"

# --- 3 and 4. the real batch: orcs-batch run on 1 and 2 workers, orcs-sim under GNU parallel ----------------
: >"$work/t1" && : >"$work/t2" && : >"$work/tp"
for r in $(seq "$repeat"); do
  for w in 1 2; do
    echo "bench_batch: orcs-batch run, $jobs jobs, $w worker(s), repetition $r/$repeat" >&2
    wait_quiet
    l0=$(load)
    status=0
    timed "$work/t$w" "run ${w}w #$r" "$build/bin/orcs-batch" run "$scenario" --jobs "$jobs" --workers "$w" \
      --out "$work/batch-w$w-r$r" --quiet >"$work/batch-w$w-r$r.txt" 2>&1 || status=$?
    loads+=("orcs-batch run ${w}w #$r: $l0→$(load)")
    [ $status -le 1 ] || { cat "$work/batch-w$w-r$r.txt" >&2; die "orcs-batch run exited $status"; }
    [ "$(wc -l <"$work/batch-w$w-r$r/results.jsonl")" -eq "$jobs" ] || die "orcs-batch run: not $jobs results"
    summary=$(grep -m1 'jobs ran' "$work/batch-w$w-r$r.txt" || true)
    echo "bench_batch:   $(tail -1 "$work/t$w") s; $summary" >&2
  done
  echo "bench_batch: GNU parallel -j2, one orcs-sim --scenario per job, $jobs jobs, repetition $r/$repeat" >&2
  wait_quiet
  l0=$(load)
  timed "$work/tp" "parallel #$r" "$parallel_bin" --will-cite -j2 --halt now,fail=1 \
    "$build/bin/orcs-sim" --scenario "$scenario" --seed {} ::: $(seq 1 "$jobs") \
    >"$work/parallel-r$r.jsonl" 2>"$work/parallel-r$r.err" ||
    { tail -5 "$work/parallel-r$r.err" >&2; die "GNU parallel: an orcs-sim failed"; }
  loads+=("parallel #$r: $l0→$(load)")
  [ "$(wc -l <"$work/parallel-r$r.jsonl")" -eq "$jobs" ] || die "GNU parallel: not $jobs result lines"
  echo "bench_batch:   $(tail -1 "$work/tp") s" >&2
done
read -r t1 t1_min t1_max < <(stats 2 <"$work/t1")
read -r t2 t2_min t2_max < <(stats 2 <"$work/t2")
read -r tp tp_min tp_max < <(stats 2 <"$work/tp")
scaling=$(awk -v a="$t1" -v b="$t2" 'BEGIN { printf "%.2f", a / b }')
batch_ok=$(count_ok "$work/batch-w2-r1/results.jsonl")
# The same jobs: orcs-sim's lines must carry the fitness orcs-batch got for the same seeds, bit for bit.
same=$("$py" - "$work/batch-w1-r1/results.jsonl" "$work/batch-w2-r1/results.jsonl" "$work/parallel-r1.jsonl" <<'EOF'
import json, sys
def by_seed(path):
    return {line["seed"]: line.get("fitness") for line in map(json.loads, open(path)) if line}
runs = [by_seed(p) for p in sys.argv[1:]]
print("identical" if all(r == runs[0] for r in runs) else "DIFFERENT")
EOF
)
[ "$same" = identical ] || echo "bench_batch: WARNING: fitness differs between the runs of the same jobs" >&2
job_seconds=$("$py" - "$work/batch-w1-r1/results.jsonl" <<'EOF'
import json, statistics, sys
t = [json.loads(l)["timings"] for l in open(sys.argv[1]) if l.strip()]
print("%.2f %.1f" % (statistics.mean(x.get("run_seconds", 0) for x in t),
                     statistics.mean(x.get("simulated_seconds", 0) for x in t)))
EOF
)
read -r job_run_seconds job_sim_seconds <<<"$job_seconds"

# --- 5. orcs-worker's resident memory -----------------------------------------------------------------------
echo "bench_batch: orcs-worker peak RSS: orcs-broker + 2 orcs-worker + orcs-batch submit, $jobs jobs" >&2
mkfifo "$work/broker.out"
"$build/bin/orcs-broker" --client-port 0 --worker-port 0 >"$work/broker.out" 2>"$work/broker.err" &
started+=($!)
broker_pid=$!
exec 3<"$work/broker.out"
read -r -t 10 -u 3 endpoints || die "orcs-broker printed no endpoints within 10 s: $(cat "$work/broker.err")"
client_endpoint=$(sed -n 's/.*clients=\([^ ]*\).*/\1/p' <<<"$endpoints")
worker_endpoint=$(sed -n 's/.*workers=\([^ ]*\).*/\1/p' <<<"$endpoints")
worker_pids=()
for i in 1 2; do
  "$build/bin/orcs-worker" --connect "$worker_endpoint" --id "rss-$i" 2>"$work/worker-$i.err" &
  started+=($!)
  worker_pids+=($!)
done
l0=$(load)
"$build/bin/orcs-batch" submit --broker "$client_endpoint" "$scenario" --jobs "$jobs" --out "$work/submit" \
  --quiet >"$work/submit.txt" 2>&1 || [ $? -eq 1 ] || { cat "$work/submit.txt" >&2; die "orcs-batch submit failed"; }
loads+=("memory: $l0→$(load)")
rss_kib=0
for i in 0 1; do
  hwm=$(awk '/^VmHWM:/ { print $2 }' "/proc/${worker_pids[$i]}/status") || die "orcs-worker ${worker_pids[$i]} is gone"
  served=$(grep -c "\"worker\":\"rss-$((i + 1))\"" "$work/submit/results.jsonl" || true)
  echo "bench_batch:   orcs-worker rss-$((i + 1)): VmHWM $hwm KiB after $served jobs" >&2
  [ "$hwm" -gt "$rss_kib" ] && rss_kib=$hwm
done
kill -TERM "${worker_pids[@]}" "$broker_pid"
for pid in "${worker_pids[@]}" "$broker_pid"; do wait "$pid" || true; done
exec 3<&-
started=()
rss_mib=$(awk -v k="$rss_kib" 'BEGIN { printf "%.1f", k / 1024 }')
rss_mb=$(awk -v k="$rss_kib" 'BEGIN { printf "%.1f", k * 1024 / 1e6 }')

# --- the table ------------------------------------------------------------------------------------------------
fmt() { "$py" -c 'import sys; print(f"{float(sys.argv[1]):,.0f}")' "$1"; }
sim_version=$(git describe --always --dirty 2>/dev/null || echo unknown)
build_type=$(sed -n 's/^CMAKE_BUILD_TYPE:STRING=//p' "$build/CMakeCache.txt" 2>/dev/null || true)
cpu=$(sed -n 's/^model name[[:space:]]*: //p' /proc/cpuinfo | head -1)
memory=$(awk '/^MemTotal:/ { printf "%.0f GiB", $2 / 1048576 }' /proc/meminfo)
date=$(date +%Y-%m-%d)
command=$invocation
scenario_name=$(basename "$scenario")
table=$(
  cat <<EOF
| measurement | median of $repeat (min–max) | target |
|---|---|---|
| broker dispatch, $(fmt "$empty_jobs") empty jobs, default settings (credit 2, short-job credit 16) | **$(fmt "$dispatch_default") jobs/s** ($(fmt "$dispatch_default_min")–$(fmt "$dispatch_default_max")) | ≥ 20,000 |
| broker dispatch, the same with the credit fixed at 2 | $(fmt "$dispatch_fixed") jobs/s ($(fmt "$dispatch_fixed_min")–$(fmt "$dispatch_fixed_max")) | |
| Dask distributed $dask_version, the same $(fmt "$empty_jobs") empty tasks, 2 worker processes | $(fmt "$dask_rate") tasks/s ($(fmt "$dask_min")–$(fmt "$dask_max")) | |
| \`orcs-batch run\`, $jobs jobs of $scenario_name, 1 worker | $t1 s ($t1_min–$t1_max) | |
| \`orcs-batch run\`, the same $jobs jobs, 2 workers | $t2 s ($t2_min–$t2_max) | |
| **scaling 1 → 2 workers** | **$scaling×** | ≥ 1.85× |
| GNU parallel -j2, one \`orcs-sim --scenario\` per job, the same $jobs jobs | $tp s ($tp_min–$tp_max) | |
| orcs-worker peak resident memory (VmHWM) after $jobs jobs on 2 workers | **$rss_mib MiB** ($rss_mb MB) | < 50 MB |
EOF
)
notes="Recorded $date on $(nproc) cores ($cpu), $memory, $(. /etc/os-release && echo "$PRETTY_NAME"), build type ${build_type:-?}, \`$sim_version\`. A job: $job_sim_seconds simulated seconds (the scenario's parameter sets together), $job_run_seconds s of worker time on average; $batch_ok of $jobs ok; fitness of every seed $same across \`orcs-batch run\` on 1 and 2 workers and \`orcs-sim\`. Other processes' CPU during each run, in cores (2 = the whole machine; hypervisor steal included): $(
  IFS=';'
  echo "${foreign[*]}" | sed 's/;/; /g'
). Load average (1 min, the benchmark's own processes included) before→after each measurement: $(
  IFS=';'
  echo "${loads[*]}" | sed 's/;/; /g'
)."

echo
echo "$table"
echo
echo "$notes"
echo
echo "Command: $command"

if [ $write_docs -eq 1 ]; then
  "$py" - docs/benchmarks.md "$table" "$notes" "$command" <<'EOF'
import sys
path, table, notes, command = sys.argv[1:5]
begin, end = "<!-- bench_batch.sh: begin -->", "<!-- bench_batch.sh: end -->"
text = open(path).read()
if begin not in text or end not in text:
    sys.exit(f"bench_batch: {path} has no '{begin}' ... '{end}' block in its Batch evaluation section")
block = f"{begin}\n```sh\n{command}\n```\n\n{table}\n\n{notes}\n{end}"
head, rest = text.split(begin, 1)
tail = rest.split(end, 1)[1]
open(path + ".tmp", "w").write(head + block + tail)
import os
os.replace(path + ".tmp", path)
print(f"bench_batch: wrote the figures into {path}", file=sys.stderr)
EOF
fi
