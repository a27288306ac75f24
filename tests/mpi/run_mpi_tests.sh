#!/usr/bin/env bash
# vpsim under `mpirun --oversubscribe -np 2` and `-np 4` on this machine: the collectives and the
# split Monte Carlo (mpi_check), `vpsim run` of a small job (the kernel's photons split over the
# ranks) giving the single process's report.json figures plus "mpi", the same job in x-y tiles
# over 2 and 4 ranks (tiles dealt round-robin, merged in order), stopped on 2 ranks and resumed
# on 4 from its checkpoint, tiled jobs with the figures and the 3D view giving one process's
# pictures byte for byte, and a batch of 3 jobs over
# 2 ranks giving the single process's per-job figures. Exits 77 (ctest: skipped) with a line
# saying why when vpsim was built without MPI or mpirun is missing.
# Usage: run_mpi_tests.sh VPSIM_BINARY MPI_CHECK_BINARY SOURCE_DIR WITH_MPI(ON|OFF)
set -uo pipefail
vpsim="$1"; check="$2"; source="$3"; with_mpi="$4"
if [[ "$with_mpi" != ON ]]; then
  echo "mpi: SKIPPED: vpsim was built without MPI (Open MPI's libopenmpi-dev not found by CMake)"
  exit 77
fi
command -v mpirun >/dev/null || { echo "mpi: SKIPPED: mpirun not found (Debian's openmpi-bin)"; exit 77; }
command -v jq >/dev/null || { echo "mpi: FAILED: jq is missing"; exit 1; }
. "$source/tests/mpi/compare_reports.sh"
# Open MPI refuses root without these; vader's single-copy (CMA) fails in containers.
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_btl_vader_single_copy_mechanism=none
# Under tools/run-sanitized-tests.sh: Open MPI loads its MCA components with dlopen and unloads
# them in MPI_Finalize, so what they keep for the process's life is reported as leaks whose
# frames have no module name left to suppress by (tests/sanitizers/lsan.supp names libraries).
# Leak checking is off for the processes mpirun starts, only; ASan's memory errors and UBSan
# still stop them, and the same vpsim code runs leak-checked in one process in the other tests.
if [[ -n "${ASAN_OPTIONS:-}" ]]; then export ASAN_OPTIONS="${ASAN_OPTIONS/detect_leaks=1/detect_leaks=0}"; fi
mpi() { local n="$1"; shift; mpirun --oversubscribe -np "$n" "$@"; }
work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
failed=0
fail() { failed=$((failed + 1)); echo "FAILED: $*"; }

for n in 2 4; do
  mpi "$n" "$check" >"$work/check$n.out" 2>&1 || { fail "mpi_check -np $n"; cat "$work/check$n.out"; }
done

job="$source/tests/cli/data/small_job.json"
few="--set kernel.photons=6000"  # 6 rounds of 1024 control batches and a remainder
# run_job NAME RANKS [ARGS...]: vpsim run into $work/NAME with a cache of its own (the kernel is
# computed, not read); RANKS 0 = no mpirun at all.
run_job() {
  local name="$1" n="$2"; shift 2
  local cmd=("$vpsim" -q run "$job" --out "$work/$name" $few "$@")
  if [[ $n -eq 0 ]]; then VPSIM_CACHE_DIR="$work/cache-$name" "${cmd[@]}"
  else VPSIM_CACHE_DIR="$work/cache-$name" mpi "$n" "${cmd[@]}"; fi >"$work/$name.log" 2>&1 ||
    { fail "vpsim run $name ($n ranks)"; cat "$work/$name.log"; }
}
run_job one 0
run_job two 2
run_job collision-one 0 --set kernel.estimator=collision
run_job collision-four 4 --set kernel.estimator=collision
jq -e 'has("mpi") | not' "$work/one/report.json" >/dev/null || fail "a plain run wrote \"mpi\""
for pair in "one two 2" "collision-one collision-four 4"; do
  set -- $pair
  [[ "$(figures "$work/$1/report.json")" == "$(figures "$work/$2/report.json")" ]] ||
    { fail "$2: report figures differ from one process's"; diff <(figures "$work/$1/report.json") \
        <(figures "$work/$2/report.json") | head -20; }
  jq -e --argjson n "$3" '.mpi.ranks == $n and (.mpi.split[0].photon_ranges | length) == $n
        and .mpi.split[0].photon_ranges[-1][1] == 6000 and .kernel.from_cache == false' \
    "$work/$2/report.json" >/dev/null || fail "$2: mpi field $(jq -c .mpi "$work/$2/report.json")"
done

# A tiled job (25 tiles of 0.3 mm, no figures: the tiles' states are small) over 2 and 4 ranks:
# the tiles dealt round-robin and merged on rank 0 in their order give one process's figures
# and the same cured.stl, byte for byte.
# bottom-narrow: down-facing walls, so the validators' over-cure runs are merged too.
tiled=(--set simulation.tile=0.3mm --set 'simulation.outputs=["cured.stl"]' --set part.test_part=bottom-narrow)
run_job tiled-one 0 "${tiled[@]}"
for n in 2 4; do
  run_job "tiled-$n" "$n" "${tiled[@]}"
  [[ "$(figures "$work/tiled-one/report.json")" == "$(figures "$work/tiled-$n/report.json")" ]] ||
    { fail "tiled-$n: report figures differ from one process's"; diff <(figures "$work/tiled-one/report.json") \
        <(figures "$work/tiled-$n/report.json") | head -20; }
  cmp -s "$work/tiled-one/cured.stl" "$work/tiled-$n/cured.stl" || fail "tiled-$n: cured.stl differs"
  jq -e --argjson n "$n" '.mpi.ranks == $n and .mpi.tiles.count == 25
        and (.mpi.tiles.tiles_of_rank | length) == $n and .mpi.tiles.tiles_of_rank[1][0] == 1' \
    "$work/tiled-$n/report.json" >/dev/null || fail "tiled-$n: mpi field $(jq -c .mpi.tiles "$work/tiled-$n/report.json")"
done

# Checkpoints over MPI (issue 22): the tiled job stopped after 6 tiles on 2 ranks (3 merged
# rounds, as a pre-emption would stop it) and resumed on 4 ranks gives one process's figures and
# cured.stl; the resumed run exposes the checkpoint's plan (its log line says so) and a finished
# run leaves no checkpoint and a manifest.
resumed="$work/tiled-resumed"
VPSIM_CACHE_DIR="$work/cache-resumed" VPSIM_STOP_AFTER_TILES=6 mpi 2 "$vpsim" -q run "$job" \
  --out "$resumed" $few "${tiled[@]}" >"$work/stopped.log" 2>&1 && fail "VPSIM_STOP_AFTER_TILES=6 did not stop the run"
grep -q "stopped after tile 6" "$work/stopped.log" || { fail "no stop after tile 6"; cat "$work/stopped.log"; }
jq -e '.tiles_done == 6' "$resumed/checkpoint/state.json" >/dev/null || fail "no checkpoint after 6 tiles"
[[ ! -e "$resumed/manifest.json" ]] || fail "an interrupted run has a manifest"
VPSIM_CACHE_DIR="$work/cache-resumed" VPSIM_LOG=info mpi 4 "$vpsim" run "$job" --out "$resumed" \
  $few "${tiled[@]}" --resume >"$work/resumed.log" 2>&1 || { fail "--resume on 4 ranks"; cat "$work/resumed.log"; }
grep -q "exposing the checkpoint's plan" "$work/resumed.log" || fail "the resumed run planned again"
grep -q "resuming after tile 6 of 25" "$work/resumed.log" || fail "the resumed run did not resume after tile 6"
[[ "$(figures "$work/tiled-one/report.json")" == "$(figures "$resumed/report.json")" ]] ||
  { fail "resumed on 4 ranks: report figures differ from one process's"; diff <(figures "$work/tiled-one/report.json") \
      <(figures "$resumed/report.json") | head -20; }
cmp -s "$work/tiled-one/cured.stl" "$resumed/cured.stl" || fail "resumed on 4 ranks: cured.stl differs"
[[ ! -e "$resumed/checkpoint" ]] || fail "a finished run left its checkpoint"
jq -e '.mpi.tiles.resumed_after_tile == 6 and .mpi.tiles.tiles_of_rank[1][0] == 7' "$resumed/report.json" >/dev/null ||
  fail "resumed: mpi field $(jq -c .mpi.tiles "$resumed/report.json")"
jq -e '[.files[].name] | map(select(startswith("checkpoint"))) | length == 0' "$resumed/manifest.json" >/dev/null ||
  fail "the manifest lists the checkpoint"

# Tiled jobs with the figures and the 3D view: each rank's share of the pictures (sections,
# layer sections, the cured surface's picture, the exposure-error map) merged on rank 0 in the
# tiles' order gives one process's pictures byte for byte: every png, svg and js file, with the
# view kept whole (0.3 mm tiles of the 1 mm part) or clustered (3 mm at 10 um, 1 mm tiles), and
# stopped on 2 ranks and resumed on 4 from a checkpoint with the pictures' state.
same_pictures() {  # same_pictures ONE OTHER: every picture and script file byte for byte
  local f n=0
  for f in "$1"/*.png "$1"/*.svg "$1"/*.js; do
    n=$((n + 1))
    cmp -s "$f" "$2/$(basename "$f")" || fail "$2: $(basename "$f") differs from one process's"
  done
  [[ $n -ge 15 ]] || fail "$1: only $n picture files"
  [[ "$(figures "$1/report.json")" == "$(figures "$2/report.json")" ]] ||
    { fail "$2: report figures differ from one process's"; diff <(figures "$1/report.json") \
        <(figures "$2/report.json") | head -20; }
}
kept=("${tiled[@]}" --set 'simulation.outputs=["cured.stl","figures","viewer"]')
clustered=(--set simulation.tile=1mm --set part.size=3mm --set simulation.voxel=10um
           --set 'simulation.outputs=["figures","viewer"]')
run_job kept-one 0 "${kept[@]}"
run_job kept-2 2 "${kept[@]}"
same_pictures "$work/kept-one" "$work/kept-2"
cmp -s "$work/kept-one/cured.stl" "$work/kept-2/cured.stl" || fail "kept-2: cured.stl differs"
jq -e '.mpi.tiles.count == 25 and .report.viewer3d.cluster_cell_um == 0' "$work/kept-2/report.json" >/dev/null ||
  fail "kept-2: $(jq -c '.mpi.tiles.count, .report.viewer3d' "$work/kept-2/report.json")"
run_job clustered-one 0 "${clustered[@]}"
for n in 2 4; do
  run_job "clustered-$n" "$n" "${clustered[@]}"
  same_pictures "$work/clustered-one" "$work/clustered-$n"
  jq -e --argjson n "$n" '.mpi.ranks == $n and .mpi.tiles.count > 4 and .report.viewer3d.cluster_cell_um > 0' \
    "$work/clustered-$n/report.json" >/dev/null || fail "clustered-$n: $(jq -c '.mpi.tiles.count, .report.viewer3d' "$work/clustered-$n/report.json")"
done
resumed="$work/clustered-resumed"
VPSIM_CACHE_DIR="$work/cache-cr" VPSIM_STOP_AFTER_TILES=4 mpi 2 "$vpsim" -q run "$job" \
  --out "$resumed" $few "${clustered[@]}" >"$work/cstopped.log" 2>&1 && fail "pictures: VPSIM_STOP_AFTER_TILES=4 did not stop the run"
ls "$resumed"/checkpoint/pictures-4.bin >/dev/null 2>&1 || fail "pictures: no pictures-4.bin after 4 tiles"
VPSIM_CACHE_DIR="$work/cache-cr" mpi 4 "$vpsim" -q run "$job" --out "$resumed" $few "${clustered[@]}" \
  --resume >"$work/cresumed.log" 2>&1 || { fail "pictures: --resume on 4 ranks"; cat "$work/cresumed.log"; }
same_pictures "$work/clustered-one" "$resumed"

# A batch of 3 jobs over 2 ranks: the same per-job figures as one process.
cat >"$work/sweep.json" <<JSON
{"job": "$job", "runs": [
  {"name": "a", "set": ["cure.critical_dose=8 mJ/cm^2"]},
  {"name": "b", "set": ["cure.critical_dose=10 mJ/cm^2"]},
  {"name": "c", "set": ["cure.critical_dose=12 mJ/cm^2"]}]}
JSON
VPSIM_CACHE_DIR="$work/cache-b1" "$vpsim" -q batch --sweep "$work/sweep.json" \
  --out "$work/batch1" $few >"$work/batch1.log" 2>&1 || { fail "batch, one process"; cat "$work/batch1.log"; }
VPSIM_CACHE_DIR="$work/cache-b2" mpi 2 "$vpsim" -q batch --sweep "$work/sweep.json" \
  --out "$work/batch2" $few >"$work/batch2.log" 2>&1 || { fail "batch, 2 ranks"; cat "$work/batch2.log"; }
jobs() { jq -S '.jobs | map({name, status, figures})' "$1"; }
[[ "$(jobs "$work/batch1/batch.json")" == "$(jobs "$work/batch2/batch.json")" ]] ||
  fail "batch over 2 ranks: per-job figures differ from one process's"
jq -e '.mpi.ranks == 2 and (.jobs | map(.rank)) == [0, 1, 0] and .failed == 0' \
  "$work/batch2/batch.json" >/dev/null || fail "batch.json over 2 ranks: $(jq -c '.mpi, (.jobs | map(.rank))' "$work/batch2/batch.json")"
for name in a b c; do
  [[ "$(figures "$work/batch1/$name/report.json")" == "$(figures "$work/batch2/$name/report.json")" ]] ||
    fail "batch job $name: report figures differ between 1 and 2 ranks"
done

[[ $failed -eq 0 ]] || { echo "mpi: $failed check(s) FAILED"; exit 1; }
echo "mpi: all checks passed (2 and 4 ranks)"
