#!/usr/bin/env bash
# Sets up, builds and runs every test: the command the README gives and CI runs (within 40 minutes on 2 cores).
# Usage: scripts/test.sh [--long]
#   --long  also the long cases (ORCS_LONG_TESTS=1): the hidden-effect families' other cases, each on both engines
#           (ORCS_GAP_BOTH_ENGINES=1); 30-60 minutes more on 2 cores (docs/benchmarks.md, "CI")
set -euo pipefail
cd "$(dirname "$0")/.."
case "${1:-}" in
  "") ;;
  --long) export ORCS_LONG_TESTS=1 ORCS_GAP_BOTH_ENGINES=1 ;;
  *) echo "test.sh: unknown option '$1' (scripts/test.sh [--long])" >&2; exit 2 ;;
esac
scripts/setup.sh
scripts/build.sh
jobs=$(nproc 2>/dev/null || echo 2)
ctest --test-dir build --output-on-failure --parallel "$jobs" --timeout 300
