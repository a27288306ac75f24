#!/usr/bin/env bash
# Golden figures: runs every job in examples/*.json through `vpsim run` and compares the figures of
# its report.json with tests/golden/figures.json under the tolerances stored there, printing a
# table per job (stored, now, difference, tolerance, OK/MOVED/MISSING/NEW), and checks each
# report.json against docs/report-schema.json (check_report.sh). Fails when a figure moved, when a
# job has no stored figures, when a report breaks the schema, or when a run fails.
# Usage: run_golden.sh VPSIM VPSIM_GOLDEN SOURCE_DIR [--update]
#   --update rewrites figures.json from this run instead (tools/update-golden.sh calls it).
set -euo pipefail
if [[ $# -lt 3 ]]; then
  echo "usage: run_golden.sh VPSIM VPSIM_GOLDEN SOURCE_DIR [--update]" >&2; exit 2
fi
vpsim="$1"; golden="$2"; source="$3"; mode="${4:-check}"
figures="$source/tests/golden/figures.json"
for program in "$vpsim" "$golden"; do
  [[ -x "$program" ]] || { echo "golden: $program is not an executable (build it first)"; exit 1; }
done
[[ -f "$figures" ]] || { echo "golden: $figures is missing"; exit 1; }
shopt -s nullglob
jobs=("$source"/examples/*.json)
[[ ${#jobs[@]} -gt 0 ]] || { echo "golden: no jobs in $source/examples"; exit 1; }

# In the build tree (ctest's working directory), not /tmp: a CI machine's /tmp can be a small
# tmpfs (the seed001 jobs write 140-180 MB each).
work="$(mktemp -d "$PWD/golden-work.XXXXXX")"; trap 'rm -rf "$work"' EXIT
# A private kernel cache: every run computes its kernel, and no user's cache is read or written.
export VPSIM_CACHE_DIR="$work/cache"
if [[ "$mode" == "--update" ]]; then
  cp "$figures" "$work/figures.json"
  "$golden" reset "$work/figures.json"
fi

failed=0
for job in "${jobs[@]}"; do
  name="$(basename "$job" .json)"
  mapfile -t run_args < <("$golden" run-args "$job")
  start=$SECONDS
  if ! "$vpsim" -q "${run_args[@]}" run "$job" --out "$work/$name" >"$work/$name.log" 2>&1; then
    echo "golden: vpsim ${run_args[*]} run $job failed:"; cat "$work/$name.log"
    failed=$((failed + 1)); continue
  fi
  echo "golden: $name ran in $((SECONDS - start)) s (vpsim ${run_args[*]} run examples/$name.json)"
  if ! bash "$source/tests/golden/check_report.sh" "$source/docs/report-schema.json" \
      "$work/$name/report.json"; then
    echo "golden: $name: report.json does not follow docs/report-schema.json"
    failed=$((failed + 1)); continue
  fi
  if [[ "$mode" == "--update" ]]; then
    "$golden" store "$work/figures.json" "$name" "$work/$name/report.json" "${run_args[@]}"
  elif ! "$golden" compare "$figures" "$name" "$work/$name/report.json" "${run_args[@]}"; then
    failed=$((failed + 1))
  fi
  rm -rf "${work:?}/$name"  # one job's files at a time: a CI machine's disk can be small
  echo
done

if [[ "$mode" == "--update" ]]; then
  if [[ $failed -ne 0 ]]; then echo "golden: $failed jobs failed, $figures left unchanged"; exit 1; fi
  cp "$work/figures.json" "$figures"
  echo "golden: wrote $figures for ${#jobs[@]} jobs; commit it with a message saying why the figures changed"
  exit 0
fi
echo "golden: ${#jobs[@]} jobs, $failed not OK"
[[ $failed -eq 0 ]]
