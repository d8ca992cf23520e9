#!/usr/bin/env bash
# Configures and builds orcs into build/ (Release with debug info, warnings as errors).
# Usage: scripts/build.sh [extra cmake arguments]
#   BUILD_DIR=DIR   build there instead of build/
#   TARGET=NAME     build only that target (default: everything)
# A build folder configured before by a plain `cmake -B build` (Unix Makefiles) is built with its own generator:
# CMake refuses to switch generators in place, and that refusal must not be the first thing a newcomer sees.
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=$(nproc 2>/dev/null || echo 2)
dir=${BUILD_DIR:-build}
generator=Ninja
if [[ -f $dir/CMakeCache.txt ]]; then
  existing=$(sed -n 's/^CMAKE_GENERATOR:INTERNAL=//p' "$dir/CMakeCache.txt")
  if [[ -n $existing && $existing != "$generator" ]]; then
    echo "build.sh: $dir/ was configured with \"$existing\" (a plain cmake -B $dir); building with it." \
         "For Ninja, remove $dir/ and run scripts/build.sh again." >&2
    generator=$existing
  fi
fi
cmake -S . -B "$dir" -G "$generator" -DORCS_WERROR=ON "$@" >/dev/null
cmake --build "$dir" --parallel "$jobs" ${TARGET:+--target "$TARGET"}
