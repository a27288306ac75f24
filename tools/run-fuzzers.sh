#!/usr/bin/env bash
# Builds the libFuzzer targets of fuzz/ with clang (ASan + UBSan) and runs each for SECONDS
# (default 20) on a copy of its seed corpus in fuzz/corpus/NAME. Exits non-zero when a target
# crashes, leaks, hangs or trips a sanitizer; the reproducer is left in build-fuzz/artifacts/.
#   tools/run-fuzzers.sh 20            # every target, 20 s each (what CI runs)
#   tools/run-fuzzers.sh 300 fuzz_stl  # one target for five minutes
set -euo pipefail
seconds="${1:-20}"; shift || true
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${VPSIM_FUZZ_BUILD:-$root/build-fuzz}"
targets=("$@")
[[ ${#targets[@]} -gt 0 ]] || targets=(fuzz_stl fuzz_config fuzz_working_curve fuzz_plan fuzz_checkpoint)

launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
cmake -S "$root/fuzz" -B "$build" -DCMAKE_CXX_COMPILER=clang++ "${launcher[@]}" >/dev/null
nice cmake --build "$build" -j"${VPSIM_FUZZ_JOBS:-2}" --target "${targets[@]}"

mkdir -p "$build/artifacts"
status=0
for target in "${targets[@]}"; do
  name="${target#fuzz_}"
  corpus="$build/corpus/$name"; mkdir -p "$corpus"
  cp -n "$root/fuzz/corpus/$name/"* "$corpus/" 2>/dev/null || true
  echo "== $target: ${seconds}s"
  if ! "$build/$target" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
      -max_len=65536 -print_final_stats=1 -artifact_prefix="$build/artifacts/$target-" \
      "$corpus" "$root/fuzz/corpus/$name" 2>"$build/$target.log"; then
    echo "FAILED: $target (log $build/$target.log, reproducer in $build/artifacts/)"
    tail -40 "$build/$target.log"
    status=1
  else
    grep -E "^stat::number_of_executed_units|^#[0-9]+.*DONE" "$build/$target.log" | tail -2 || true
  fi
done
exit $status
