#!/usr/bin/env bash
# Installs the Debian packages orcs builds against. Idempotent: quiet when everything is present.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config
  libode-dev            # ODE 0.16, double precision
  libmujoco-dev         # MuJoCo 2.2.2: the second physics backend (model/physics/mujoco/)
  libeigen3-dev         # Eigen 3.4
  libzmq3-dev cppzmq-dev
  protobuf-compiler libprotobuf-dev
  nlohmann-json3-dev
  libtinyxml2-dev
  libcli11-dev
  libgtest-dev libgmock-dev
  libbenchmark-dev
  python3
  python3-matplotlib    # scripts/plot_*.py (orcs-batch sweep plots, orcs-gap plots)
  libpagmo-dev          # pagmo2: CMA-ES for orcs-gap's simulation-in-the-loop fits
  libsqlite3-dev        # the broker's journal (orcs-broker --journal)
  slurm-wlm munge       # tests/integration/slurm: a private single-node Slurm runs scripts/slurm/*.sbatch
  clang-14 libclang-rt-14-dev  # libFuzzer and the sanitizers for scripts/fuzz.sh (tests/fuzz/)
  python3-zmq python3-protobuf  # clients/python: the Python BatchClient (pyzmq, protobuf 3.21 like protoc)
  zlib1g-dev            # recordings (*.orcsrec): one zlib stream of frames (docs/recording.md)
  libcpp-httplib-dev    # orcs-view's HTTP server (viewer/)
  libre2-dev            # linear-time regular expressions for user-supplied patterns (the viewer's search)
  liblua5.4-dev         # Lua 5.4: scripted fitness terms and controllers that travel in jobs (model/script/)
  libserialport-dev     # the Dynamixel bus on a real serial port (hardware/serial/, docs/hardware.md)
  libceres-dev          # Ceres Solver: orcs-gap's Levenberg–Marquardt polish and the Jacobian of its confidence intervals
  chromium              # orcs-view --render (headless, WebGL through SwiftShader) and tests/browser/
  ffmpeg                # orcs-view --render: PNG frames into a GIF or MP4 clip
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
# The viewer page's scripts (three.js, uPlot) and the browser tests' driver come from pinned npm packages.
command -v npm >/dev/null || missing+=(nodejs npm)
if [ ${#missing[@]} -eq 0 ]; then
  exec "$(dirname "$0")/setup_web.sh"
fi

echo "setup: installing ${missing[*]}"
sudo_cmd=()
[ "$(id -u)" -ne 0 ] && sudo_cmd=(sudo)
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
"$(dirname "$0")/setup_web.sh"
