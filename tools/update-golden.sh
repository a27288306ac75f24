#!/usr/bin/env bash
# Regenerates tests/golden/figures.json from a run of every examples/*.json job (the golden test's
# stored figures; its tolerances are kept). A deliberate change of figures updates them in the same
# commit and says in the message why they moved. Builds vpsim and vpsim_golden in BUILD_DIR
# (default ./build) first.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${BUILD_DIR:-$root/build}"
cmake --build "$build" -j "$(nproc)" --target vpsim_cli vpsim_golden
(cd "$build" && bash "$root/tests/golden/run_golden.sh" "$build/vpsim" "$build/tests/vpsim_golden" \
  "$root" --update)  # its work directory goes in the build tree
git -C "$root" --no-pager diff --stat -- tests/golden/figures.json || true
