#!/usr/bin/env bash
# Installs what is missing, then configures and builds vpsim (Release) in ./build.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$root/tools/install-deps.sh"
cmake -S "$root" -B "$root/build" -DCMAKE_BUILD_TYPE=Release -DVPSIM_BUILD_TESTS=ON -DVPSIM_BUILD_BENCHMARKS=ON
cmake --build "$root/build" -j "$(nproc)"
