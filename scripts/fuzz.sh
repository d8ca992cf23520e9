#!/usr/bin/env bash
# scripts/fuzz.sh SECONDS [TARGET...]: runs every libFuzzer target (tests/fuzz/, docs/reliability.md "Fuzzing") for
# SECONDS each, starting from its seed corpus copied to a temporary folder (the committed corpus never grows).
# Configures and builds build-fuzz (clang-14, ASan + UBSan) when needed. Exits non-zero when any target crashed,
# hung or leaked, naming the input that did it; the input is kept under build-fuzz/crashes/<target>/.
set -euo pipefail

seconds=${1:?usage: scripts/fuzz.sh SECONDS [TARGET...]}
shift
root=$(cd "$(dirname "$0")/.." && pwd)
build="$root/build-fuzz"
targets=("$@")
[ ${#targets[@]} -eq 0 ] && targets=(environment_xml value_file motion_record scenario_json broker_message
                                     osp_datagram odcp_datagram measured_run view_request)

"$root/scripts/setup.sh"
if [ ! -f "$build/build.ninja" ]; then
  cmake -S "$root" -B "$build" -G Ninja -DCMAKE_CXX_COMPILER=clang++-14 -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DORCS_FUZZ=ON -DORCS_BUILD_TESTS=OFF -DORCS_BUILD_BENCHMARKS=OFF >/dev/null
fi
cmake --build "$build" -j1 --target orcs-fuzz-seeds $(printf '%s_fuzz ' "${targets[@]}")

work=$(mktemp -d /tmp/orcs-fuzz.XXXXXX)
trap 'rm -rf "$work"' EXIT
"$build/bin/orcs-fuzz-seeds" "$work/seeds"

# The usual per-process file limit, so that running out of sockets or files is a finding here as on users' machines.
ulimit -n 1024
failed=()
printf '%-16s %8s %12s %8s %s\n' target seconds executions corpus result
for target in "${targets[@]}"; do
  corpus="$work/corpus/$target"
  mkdir -p "$corpus" "$build/crashes/$target"
  cp "$work/seeds/$target"/* "$corpus/"
  [ -d "$root/tests/fuzz/regressions/$target" ] && cp "$root/tests/fuzz/regressions/$target"/* "$corpus/"
  log="$build/crashes/$target/fuzz.log"
  # -timeout: an input running longer is a hang; -rss_limit_mb: a runaway allocation is a finding too.
  status=0
  (cd "$work" && "$build/fuzz/${target}_fuzz" "$corpus" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
      -max_len=8192 -artifact_prefix="$build/crashes/$target/" -print_final_stats=1) >"$log" 2>&1 || status=$?
  executions=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo '?')
  size=$(ls "$corpus" | wc -l)
  if [ "$status" -eq 0 ]; then
    printf '%-16s %8s %12s %8s %s\n' "$target" "$seconds" "$executions" "$size" ok
  else
    artifact=$(grep -o 'Test unit written to .*' "$log" | sed 's/Test unit written to //' | tail -1)
    printf '%-16s %8s %12s %8s %s\n' "$target" "$seconds" "$executions" "$size" "FAILED: ${artifact:-see $log}"
    failed+=("$target")
  fi
done

if [ ${#failed[@]} -gt 0 ]; then
  echo "fuzz: ${failed[*]} failed; logs and inputs under $build/crashes/<target>/" >&2
  exit 1
fi
