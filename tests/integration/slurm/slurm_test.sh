#!/usr/bin/env bash
# Issue 7 item 1: a real batch through Slurm gives the same bits as `orcs-batch run`.
#
# Starts a private single-node Slurm on loopback (munged, slurmctld and slurmd with every file under a temporary
# folder), runs a 200-job A-Series batch with scripts/slurm/orcs-batch.sbatch (`sbatch --wait`) and the same batch
# with `orcs-batch run --workers 2`, and compares every result bit for bit (compare_results.py). Then checks that
# the script's exit status follows the batch's, and that scripts/slurm/orcs-workers.sbatch adds workers to a
# broker outside Slurm. Prints both batches' times (docs/cluster.md records them).
# Stops everything it started on exit, also on failure.
#
# Usage: slurm_test.sh BIN_DIR SOURCE_DIR
# Exits 0 on success, 1 on failure, 77 (skipped) only when Slurm cannot be installed or started here; with
# ORCS_REQUIRE_SLURM=1 that is a failure too.
set -euo pipefail

bin=$(realpath "$1")
src=$(realpath "$2")
readonly bin src
readonly jobs=200

say() { echo "slurm_test: $*"; }
fail() { echo "slurm_test: FAIL: $*" >&2; exit 1; }
skip() {
  [ "${ORCS_REQUIRE_SLURM:-0}" = 1 ] && fail "$* (ORCS_REQUIRE_SLURM=1: no skipping)"
  echo "slurm_test: SKIP: $*" >&2
  exit 77
}

# Polls COMMAND every 0.2 s until it succeeds, then says WHAT (if any); fails after SECONDS.
# Usage: await SECONDS WHAT COMMAND...
await() {
  local deadline=$((SECONDS + $1)) what=$2
  shift 2
  until "$@" >/dev/null 2>&1; do
    [ "$SECONDS" -ge "$deadline" ] && return 1
    sleep 0.2
  done
  [ -z "$what" ] || say "$what"
}

# --- Slurm and munge installed? (scripts/setup.sh lists them, so CI has them) ------------------------------
need=(munged mungekey munge unmunge slurmctld slurmd sbatch srun sinfo squeue scancel)
missing_commands() { local c; for c in "${need[@]}"; do command -v "$c" >/dev/null || echo "$c"; done; }
if [ -n "$(missing_commands)" ]; then
  if [ "$(id -u)" -eq 0 ] || sudo -n true 2>/dev/null; then
    say "installing slurm-wlm and munge with scripts/setup.sh"
    "$src/scripts/setup.sh" || skip "scripts/setup.sh could not install slurm-wlm and munge"
  else
    skip "slurm-wlm and munge are not installed, and installing them needs root or sudo"
  fi
  [ -z "$(missing_commands)" ] || skip "no $(missing_commands | tr '\n' ' ')on PATH after scripts/setup.sh"
fi
command -v python3 >/dev/null || fail "python3 is needed to compare results"

# --- A private cluster under a temporary folder ---------------------------------------------------------------
tmp=$(mktemp -d /tmp/orcs-slurm.XXXXXX)
chmod 755 "$tmp"  # slurmd runs jobs as this user; the folder must be reachable by them
readonly tmp
pids=()
export SLURM_CONF=$tmp/slurm.conf  # every Slurm command and daemon below reads this configuration

# Ends every process that still carries this test's SLURM_CONF in its environment: the daemons, and whatever
# they started (slurmstepd, the job's broker and workers). Precise: no other process has this path.
ours() {
  local p
  for p in /proc/[0-9]*; do
    case "${p#/proc/}" in "$$" | "$BASHPID") continue ;; esac  # this script, and the subshell running ours
    grep -qzx "SLURM_CONF=$SLURM_CONF" "$p/environ" 2>/dev/null && echo "${p#/proc/}"
  done
  return 0
}
cleanup() {
  local status=$?
  set +e
  trap - EXIT
  if [ -n "${broker_pid:-}" ]; then kill "$broker_pid" 2>/dev/null; fi
  if [ ${#pids[@]} -gt 0 ]; then
    scancel --quiet --user="$(id -un)" 2>/dev/null
    kill "${pids[@]}" 2>/dev/null
    local deadline=$((SECONDS + 10))
    while [ -n "$(ours)" ] && [ "$SECONDS" -lt "$deadline" ]; do sleep 0.2; done
    local left
    mapfile -t left < <(ours)
    if [ ${#left[@]} -gt 0 ]; then say "killing what did not stop: ${left[*]}"; kill -KILL "${left[@]}" 2>/dev/null; fi
    say "stopped the daemons and everything they started"
  fi
  if [ $status -ne 0 ] && [ $status -ne 77 ]; then
    for log in "$tmp"/log/*.log; do [ -f "$log" ] && { echo "--- $log (last lines)"; tail -n 20 "$log"; }; done
  fi
  rm -rf "$tmp"
  exit $status
}
trap cleanup EXIT
trap 'exit 1' INT TERM

mkdir -p "$tmp"/{munge,state,spool,log,run,out}
chmod 700 "$tmp/munge"

# munged with its own key and socket, so the test needs no system munge and touches no system key.
mungekey --create --keyfile="$tmp/munge/munge.key" || skip "mungekey cannot create a key"
munge_socket=$tmp/munge/munge.socket
munged --foreground --force --socket="$munge_socket" --key-file="$tmp/munge/munge.key" \
  --log-file="$tmp/log/munged.log" --pid-file="$tmp/run/munged.pid" --seed-file="$tmp/munge/munged.seed" \
  >"$tmp/log/munged.out" 2>&1 &
pids+=($!)
await 10 "munged answers on $munge_socket" bash -c "munge -n -S '$munge_socket' | unmunge -S '$munge_socket'" ||
  skip "munged did not start: $(tail -n 3 "$tmp/log/munged.log" "$tmp/log/munged.out" 2>/dev/null | tr '\n' ' ')"

# Two free loopback ports for slurmctld and slurmd (bound, then released).
read -r ctld_port slurmd_port < <(python3 -c '
import socket
s = [socket.socket() for _ in range(2)]
for x in s: x.bind(("127.0.0.1", 0))
print(*[x.getsockname()[1] for x in s])')
node=$(hostname -s)
cpus=$(nproc)
user=$(id -un)
cat >"$SLURM_CONF" <<EOF
# A single-node Slurm for orcs' integration test: everything on loopback and under $tmp.
ClusterName=orcstest
SlurmctldHost=$node(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
# Listen on SlurmctldHost's and NodeAddr's address (127.0.0.1), not on every interface, which is Slurm's default.
CommunicationParameters=NoCtldInAddrAny,NoInAddrAny
SlurmUser=$user
SlurmdUser=$user
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$munge_socket
StateSaveLocation=$tmp/state
SlurmdSpoolDir=$tmp/spool
SlurmctldPidFile=$tmp/run/slurmctld.pid
SlurmdPidFile=$tmp/run/slurmd.pid
SlurmctldLogFile=$tmp/log/slurmctld.log
SlurmdLogFile=$tmp/log/slurmd.log
SlurmctldDebug=info
SlurmdDebug=info
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MpiDefault=none
SwitchType=switch/none
ReturnToService=2
MailProg=/bin/true
KillWait=5
# sbatch --wait polls every 2 s while MinJobAge/2 <= 2, else backs off to 8 and 32 s; 5 s keeps it at 2 s and a
# finished job's record (sbatch reads its exit code there) lives at least 5 s, until slurmctld's next purge.
InactiveLimit=0
MinJobAge=5
NodeName=$node NodeAddr=127.0.0.1 CPUs=$cpus State=UNKNOWN
PartitionName=test Nodes=$node Default=YES MaxTime=INFINITE State=UP
EOF

slurmctld -D -i -f "$SLURM_CONF" >"$tmp/log/slurmctld.out" 2>&1 &
pids+=($!)
slurmd -D -f "$SLURM_CONF" >"$tmp/log/slurmd.out" 2>&1 &
pids+=($!)
last_lines() { tail -q -n 2 "$tmp/log/$1.out" "$tmp/log/$1.log" 2>/dev/null | tr '\n' ' '; }
# A child that exited stays a zombie until this shell reaps it, and kill -0 still finds it.
running() { [ "$(sed 's/.*) //' "/proc/$1/stat" 2>/dev/null | cut -c1)" != Z ] && [ -e "/proc/$1" ]; }
# Idle, or a daemon gone (no point waiting longer); at most 60 s.
node_idle() {
  [ "$(sinfo -h -N -n "$node" -o %T 2>/dev/null)" = idle ] || ! running "${pids[1]}" || ! running "${pids[2]}"
}
await 60 "" node_idle ||
  skip "Slurm did not bring node $node up within 60 s: $(sinfo -h -N -o '%N %T %E' 2>&1 | head -n 1);" \
    "slurmctld: $(last_lines slurmctld) slurmd: $(last_lines slurmd)"
running "${pids[1]}" || skip "slurmctld could not start: $(last_lines slurmctld)"
running "${pids[2]}" || skip "slurmd could not start: $(last_lines slurmd)"
say "node $node is idle (slurmctld on 127.0.0.1:$ctld_port, slurmd on :$slurmd_port, $cpus CPUs)"

# --- The same 200-job batch locally and through Slurm ---------------------------------------------------------
scenario=$src/tests/integration/slurm/slurm_batch.json
workers=$((cpus < 2 ? cpus : 2))
batch=(--jobs "$jobs" --seed 1)
now() { date +%s.%N; }
seconds_since() { python3 -c "import sys; print(f'{float(sys.argv[2]) - float(sys.argv[1]):.1f}')" "$1" "$(now)"; }

start=$(now)
timeout 600 "$bin/orcs-batch" run "$scenario" "${batch[@]}" --workers "$workers" --out "$tmp/out/local" \
  >"$tmp/log/local.log" 2>&1 || fail "orcs-batch run failed: $(tail -n 3 "$tmp/log/local.log")"
local_seconds=$(seconds_since "$start")
rate() { grep -o '[0-9.]* jobs/s in [0-9.]* s' "$1"; }  # orcs-batch's summary: the batch's own time
say "orcs-batch run, $workers local workers: $jobs jobs in $local_seconds s ($(rate "$tmp/log/local.log"))"

# Runs scripts/slurm/orcs-batch.sbatch with sbatch --wait, for at most SECONDS, on the allocation ALLOCATION (an
# sbatch option); prints sbatch's exit status (the job's). Usage: sbatch_batch NAME SECONDS ALLOCATION ARGUMENTS...
sbatch_batch() {
  local name=$1 limit=$2 allocation=$3
  shift 3
  local status=0
  timeout "$limit" sbatch --wait --quiet --job-name="orcs-$name" "$allocation" --time=10 \
    --output="$tmp/log/sbatch-$name.log" --export="ALL,ORCS_BIN=$bin" \
    "$src/scripts/slurm/orcs-batch.sbatch" "$@" >"$tmp/log/sbatch-$name.out" 2>&1 || status=$?
  echo "$status"
}

start=$(now)
status=$(sbatch_batch same 600 --ntasks="$workers" "$scenario" "$tmp/out/slurm" "${batch[@]}")
slurm_seconds=$(seconds_since "$start")
[ "$status" = 0 ] ||
  fail "the batch through Slurm exited $status: $(tail -n 5 "$tmp/log/sbatch-same.log" "$tmp/log/sbatch-same.out")"
say "orcs-batch.sbatch, $workers Slurm workers: $jobs jobs in $slurm_seconds s from sbatch to its return" \
  "($(rate "$tmp/log/sbatch-same.log"))"

sed 's/^/  job: /' "$tmp/log/sbatch-same.log"

# Broker, workers and client spoke CURVE with keys made for the job alone, and the keys are gone afterwards.
grep -q "CURVE keys $tmp/out/slurm/.orcs-keys-" "$tmp/log/sbatch-same.log" ||
  fail "orcs-batch.sbatch did not make CURVE keys for its job: $(grep broker "$tmp/log/sbatch-same.log")"
grep -q -- '--curve-keys' "$src/scripts/slurm/orcs-workers.sbatch" || fail "orcs-workers.sbatch passes no --curve-keys"
if compgen -G "$tmp/out/slurm/.orcs-keys-*" >/dev/null; then fail "the job's CURVE keys were left in $tmp/out/slurm"; fi

# Every job once, ok, and the same bits as the local run; Slurm's workers ran them.
compare=(python3 "$src/tests/integration/slurm/compare_results.py" "$tmp/out/local/results.jsonl")
"${compare[@]}" "$tmp/out/slurm/results.jsonl" --seeds "$jobs" --workers "$workers" || fail "results differ"

# The job left nothing running: broker and workers stopped with it.
no_orcs_left() {
  local p
  for p in $(ours); do case "$(cat "/proc/$p/comm" 2>/dev/null)" in orcs-*) return 1 ;; esac; done
}
await 10 "no orcs-broker or orcs-worker left after the job" no_orcs_left ||
  fail "orcs processes left after the job: $(for p in $(ours); do tr '\0' ' ' <"/proc/$p/cmdline"; echo; done)"
grep -q 'stopped: told' "$tmp/out/slurm/broker.log" ||
  fail "the broker did not stop cleanly: $(tail -n 3 "$tmp/out/slurm/broker.log")"

# --- The job's exit status is the batch's ---------------------------------------------------------------------
# One task with $workers CPUs still gets a worker per CPU.
status=$(sbatch_batch timeout 120 --cpus-per-task="$workers" "$scenario" "$tmp/out/timeout" --jobs 2 --time-limit 0.001)
[ "$status" = 1 ] || fail "a batch whose jobs time out should exit 1 through Slurm, not $status"
grep -q " $workers workers on $node" "$tmp/log/sbatch-timeout.log" ||
  fail "--cpus-per-task=$workers should give $workers workers: $(grep workers "$tmp/log/sbatch-timeout.log")"
grep -q '0 ok, 2 failed (timeout 2)' "$tmp/log/sbatch-timeout.log" ||
  fail "no timeout summary: $(tail -n 3 "$tmp/log/sbatch-timeout.log")"
status=$(sbatch_batch bad 120 --ntasks=1 "$tmp/no-such-scenario.json" "$tmp/out/bad")
[ "$status" = 2 ] || fail "a batch with a missing scenario should exit 2 through Slurm, not $status"
grep -q 'no-such-scenario.json' "$tmp/log/sbatch-bad.log" ||
  fail "the missing scenario is not named: $(tail -n 3 "$tmp/log/sbatch-bad.log")"
say "through Slurm, timed-out jobs exit 1 and a missing scenario exits 2, as orcs-batch does"

# --- A broker outside Slurm, workers from a job array ---------------------------------------------------------
"$bin/orcs-broker" --client-port 0 --worker-port 0 >"$tmp/log/broker.endpoints" 2>"$tmp/log/broker.log" &
broker_pid=$!
await 10 "orcs-broker outside Slurm is listening" grep -q '^orcs-broker clients=' "$tmp/log/broker.endpoints" ||
  fail "orcs-broker did not start: $(tail -n 2 "$tmp/log/broker.log")"
read -r _ clients worker_endpoint <"$tmp/log/broker.endpoints"
array=$(sbatch --parsable --array=1-"$workers" --time=10 --output="$tmp/log/array-%A_%a.log" \
  --export="ALL,ORCS_BIN=$bin" "$src/scripts/slurm/orcs-workers.sbatch" "${worker_endpoint#workers=}") ||
  fail "sbatch --array refused orcs-workers.sbatch"
array=${array%%;*}
# Every array worker joins before the batch goes in, so that each gets jobs (a 10-job batch can end before a late
# worker arrives).
all_joined() { [ "$(grep -c ' joined with credit' "$tmp/log/broker.log")" = "$workers" ]; }
await 30 "all $workers array workers joined the broker" all_joined ||
  fail "expected $workers array workers to join the broker: $(grep joined "$tmp/log/broker.log")"
timeout 300 "$bin/orcs-batch" submit --broker "${clients#clients=}" "$scenario" --jobs 10 --seed 1 \
  --out "$tmp/out/array" >"$tmp/log/array-batch.log" 2>&1 ||
  fail "the batch on the array's workers failed: $(tail -n 3 "$tmp/log/array-batch.log")"
"${compare[@]}" "$tmp/out/array/results.jsonl" --seeds 10 --workers "$workers" || fail "the array's results differ"
scancel "$array"
array_gone() { [ -z "$(squeue -h -j "$array" 2>/dev/null)" ] && no_orcs_worker_left; }
no_orcs_worker_left() {
  local p
  for p in $(ours); do [ "$(cat "/proc/$p/comm" 2>/dev/null)" = orcs-worker ] && return 1; done
  return 0
}
await 30 "scancel stopped the array's workers" array_gone ||
  fail "the array's workers did not stop: $(squeue -j "$array")"
# SIGTERM from scancel reached the workers: each told the broker it was leaving.
[ "$(grep -c 'worker .* left (worker shutting down)' "$tmp/log/broker.log")" = "$workers" ] ||
  fail "the array's workers did not say goodbye to the broker: $(grep worker "$tmp/log/broker.log" | tail -n 3)"
say "scancel's SIGTERM reached the array's $workers workers: each told the broker it was leaving"
say "passed"
