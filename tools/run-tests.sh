#!/usr/bin/env bash
# The README's test command: set up, build, and run the whole test suite (GPU tests on lavapipe
# under the Vulkan validation layer).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$root/tools/build.sh"
cd "$root/build"
ctest --output-on-failure -j "$(nproc)"
