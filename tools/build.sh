#!/usr/bin/env bash
# Installs what is missing, then configures and builds vpsim (Release) in ./build.
# With CI=true (set by CI services and by .ci/run) the same build has warnings as errors
# (VPSIM_WERROR=ON): a warning in vpsim's own code fails CI without a build of its own.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$root/tools/install-deps.sh"
options=()
if [[ "${CI:-}" == true ]]; then options+=(-DVPSIM_WERROR=ON); fi
cmake -S "$root" -B "$root/build" -DCMAKE_BUILD_TYPE=Release -DVPSIM_BUILD_TESTS=ON \
  -DVPSIM_BUILD_BENCHMARKS=ON "${options[@]}"
cmake --build "$root/build" -j "$(nproc)"
