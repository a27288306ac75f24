#!/usr/bin/env bash
# Builds and runs every benchmark; each prints one JSON object.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$root/tools/build.sh"
for bench in "$root"/build/benchmarks/bench_*; do
  [[ -x "$bench" ]] || continue
  echo "== $(basename "$bench")" >&2
  "$bench"
done
