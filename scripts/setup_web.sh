#!/usr/bin/env bash
# Installs the pinned npm packages of the viewer page (viewer/web: three.js, uPlot) and of the browser tests
# (tests/browser: playwright-core, which drives Debian's chromium) from their lockfiles. Quiet when they are
# installed already: a folder's node_modules is redone only when its package-lock.json changed.
set -euo pipefail
cd "$(dirname "$0")/.."
for dir in viewer/web tests/browser; do
  [ -f "$dir/package-lock.json" ] || continue
  stamp="$dir/node_modules/.orcs-lock-stamp"
  if [ -f "$stamp" ] && cmp -s "$stamp" "$dir/package-lock.json"; then continue; fi
  echo "setup: npm ci in $dir"
  npm ci --prefix "$dir" --no-audit --no-fund --loglevel=error >/dev/null
  cp "$dir/package-lock.json" "$stamp"
done
