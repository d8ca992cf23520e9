#!/usr/bin/env bash
# Configures and builds orcs into build/ (Release with debug info, warnings as errors).
# Usage: scripts/build.sh [extra cmake arguments]
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=$(nproc 2>/dev/null || echo 2)
cmake -S . -B build -G Ninja -DORCS_WERROR=ON "$@" >/dev/null
cmake --build build --parallel "$jobs"
