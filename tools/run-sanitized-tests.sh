#!/usr/bin/env bash
# Builds vpsim with AddressSanitizer + UndefinedBehaviorSanitizer (VPSIM_SANITIZE=ON) in its own
# directory, ./build-asan, and runs the whole ctest suite under them. Any ASan error, leak or UB
# report fails the test that caused it (UB does not recover: -fno-sanitize-recover=undefined).
#
# Usage: bash tools/run-sanitized-tests.sh [ctest arguments, e.g. -R cure or -L gpu]
# Environment: BUILD_DIR (default ./build-asan), JOBS (default nproc).
#
# -O1 -g: fast enough to run the suite, with usable stack traces; NDEBUG is not defined, so
# assert() is checked too. Third-party libraries that are not built here (Mesa's lavapipe, the
# Vulkan loader and validation layer, TBB) are not instrumented; the few reports they cause are
# suppressed by name in tests/sanitizers/*.supp, each with its reason. Our own code is never
# suppressed.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${BUILD_DIR:-$root/build-asan}"
jobs="${JOBS:-$(nproc)}"
launcher=()
if command -v ccache >/dev/null; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi

cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g" -DVPSIM_SANITIZE=ON -DVPSIM_BUILD_TESTS=ON \
  -DVPSIM_BUILD_BENCHMARKS=OFF "${launcher[@]}"
cmake --build "$build" -j "$jobs"

supp="$root/tests/sanitizers"
export ASAN_OPTIONS="detect_leaks=1:halt_on_error=1:strict_string_checks=1:check_initialization_order=1:detect_stack_use_after_return=1"
export LSAN_OPTIONS="suppressions=$supp/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="suppressions=$supp/ubsan.supp:print_stacktrace=1:halt_on_error=1"
cd "$build"
ctest --output-on-failure -j "$jobs" "$@"
