#!/usr/bin/env bash
# End-to-end checks of the vpsim CLI. Every command (run, kernel, slice, part, mie, mc, calibrate,
# devices) is run on good input, and its output is checked against values computed independently
# (published Mie and slab values, closed forms, a least-squares fit done here in awk); bad input
# gives exactly one clear line on stderr naming the file/key and the reason, a non-zero exit code,
# nothing on stdout and no output file.
# A missing command, input file or tool is a failure, never a skipped check. No particular Vulkan
# driver is assumed: without any device `devices` must fail with one clear line (a failure too when
# VPSIM_REQUIRE_GPU=1), and the physics commands fall back to the CPU.
# Usage: run_cli_tests.sh VPSIM_BINARY DATA_DIR SOURCE_DIR
set -uo pipefail
if [[ $# -ne 3 ]]; then
  echo "usage: run_cli_tests.sh VPSIM_BINARY DATA_DIR SOURCE_DIR" >&2; exit 2
fi
vpsim="$1"; data="$2"; source="$3"
die() { echo "cli: FAILED: $*"; exit 1; }

materials="$source/examples/materials"
table1="$source/tests/data/reference/seed001_table1_working_curve.csv"
[[ -x "$vpsim" ]] || die "$vpsim is not an executable"
command -v jq >/dev/null || die "jq is missing (tools/debian-packages.txt)"
command -v awk >/dev/null || die "awk is missing"
for file in "$data/unknown_key.json" "$data/wrong_unit.json" "$data/malformed.json" \
            "$data/small_job.json" "$data/bad_job_unknown_key.json" "$table1" \
            "$materials/alumina-seed000.json" "$materials/vandehulst-slab.json"; do
  [[ -f "$file" ]] || die "input file $file is missing"
done
# `vpsim NOSUCH --help` prints the main help and exits 0: the usage line must name the command.
for command in devices run kernel slice part mie mc calibrate; do
  "$vpsim" "$command" --help 2>&1 | grep -qE "^Usage: .*vpsim $command " ||
    die "vpsim has no '$command' command"
done

work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
export VPSIM_CACHE_DIR="$work/cache"  # the run's kernel is computed, no user cache is touched
passed=0; failed=0
fail() { failed=$((failed + 1)); echo "FAILED: $*"; }

# expect_error PATTERN ARGS...: exit != 0, stdout empty, stderr one line matching PATTERN.
expect_error() {
  local pattern="$1"; shift
  "$vpsim" -q "$@" >"$work/out" 2>"$work/err"; local code=$?
  local lines; lines=$(wc -l <"$work/err")
  if [[ $code -ne 0 && ! -s "$work/out" && $lines -eq 1 ]] && grep -qE -- "$pattern" "$work/err"; then
    passed=$((passed + 1))
  else
    fail "vpsim $* (exit $code, $lines stderr lines, expected /$pattern/)"; cat "$work/err" "$work/out"
  fi
}

# expect_ok PATTERN ARGS...: exit 0 and stdout matches PATTERN (extended regex).
expect_ok() {
  local pattern="$1"; shift
  if "$vpsim" -q "$@" >"$work/out" 2>"$work/err" && grep -qE -- "$pattern" "$work/out"; then
    passed=$((passed + 1))
  else
    fail "vpsim $* (expected /$pattern/ on stdout)"; cat "$work/err" "$work/out"
  fi
}

# expect_no_output PATH ARGS...: as expect_error with any message, and PATH was not written.
expect_no_output() {
  local path="$1"; shift
  expect_error "error: " "$@"
  if [[ -e "$path" ]]; then fail "vpsim $* wrote $path despite the error"; fi
}

# run_ok NAME ARGS...: exit 0; stdout kept in $work/NAME.json for `check`.
run_ok() {
  local name="$1"; shift
  if "$vpsim" -q "$@" >"$work/$name.json" 2>"$work/$name.err"; then
    passed=$((passed + 1))
  else
    fail "vpsim $* (exit $?)"; cat "$work/$name.err" "$work/$name.json"
  fi
}

# check FILE JQ_EXPRESSION...: each expression is true for the JSON in FILE.
check() {
  local file="$1"; shift
  for expression in "$@"; do
    if jq -e "$expression" "$file" >/dev/null 2>"$work/jq.err"; then
      passed=$((passed + 1))
    else
      fail "$(basename "$file"): $expression"; cat "$work/jq.err"; jq -c . "$file" | head -c 2000; echo
    fi
  done
}

# check_files PATH...: each exists and is not empty.
check_files() {
  for path in "$@"; do
    if [[ -s "$path" ]]; then passed=$((passed + 1)); else fail "$path missing or empty"; fi
  done
}

# --- global options and devices ---------------------------------------------------------------
run_ok version --version
grep -qE '^vpsim [0-9]' "$work/version.json" || fail "--version: $(cat "$work/version.json")"
expect_error "backend" --backend cuda devices
if "$vpsim" -q devices --json >"$work/devices.json" 2>"$work/devices.err"; then
  check "$work/devices.json" '.devices | length > 0' \
    '.devices | all(.name | type == "string" and length > 0)' \
    '.devices | all(.type | IN("discrete", "integrated", "virtual", "cpu", "other"))' \
    '.devices | all(.max_storage_buffer_range > 0 and .max_workgroup_count[0] >= 65535)' \
    '[.devices[].index] == [range(.devices | length)]'
elif [[ "${VPSIM_REQUIRE_GPU:-0}" == 1 ]]; then
  fail "devices: no Vulkan device and VPSIM_REQUIRE_GPU=1"; cat "$work/devices.err"
elif [[ $(wc -l <"$work/devices.err") -eq 1 ]] && grep -q "Vulkan" "$work/devices.err"; then
  echo "cli: no Vulkan device ($(cat "$work/devices.err")); device listing checked for its error only"
  passed=$((passed + 1))
else
  fail "devices failed without one clear line"; cat "$work/devices.err"
fi

# --- mie -----------------------------------------------------------------------------------------
expect_error "unknown_key.json: key 'particles.radus': unknown key" mie --material "$data/unknown_key.json" --json
expect_error "wrong_unit.json: key 'particles.radius': expected length" mie --material "$data/wrong_unit.json" --json
expect_error "malformed.json:3: malformed JSON" mie --material "$data/malformed.json" --json
expect_error "missing.json: cannot read" mie --material "$data/missing.json" --json
expect_error "size parameter" mie --m 1.5 --x -1 --json
# Wiscombe's (1979) test case m = 1.5 - 0.1i, x = 10: Qext 2.459791, Qsca 1.235144, g 0.922350.
run_ok mie_sphere mie --m 1.5-0.1i --x 10 --angles 0,140,180 --json
check "$work/mie_sphere.json" '(.qext - 2.459791 | fabs) < 2e-6' '(.qsca - 1.235144 | fabs) < 2e-6' \
  '(.g - 0.922350 | fabs) < 2e-6' '(.qabs - (.qext - .qsca) | fabs) < 1e-9' \
  '.s1[0] == .s2[0]' '.angles_deg == [0, 140, 180]'
# Rayleigh limit x = 0.01, m = 1.5: Qsca = 8/3 x^4 ((m^2-1)/(m^2+2))^2 = 2.30682e-9, g -> 0.
run_ok mie_rayleigh mie --m 1.5 --x 0.01 --json
check "$work/mie_rayleigh.json" '(.qsca / 2.306821e-9 - 1 | fabs) < 1e-4' '(.g | fabs) < 1e-4'
# The slurry: x = 2 pi r n_resin / lambda = 2 pi 2.5 um 1.45 / 405 nm, m = 1.75 / 1.45, and
# mua = 1 / Dp of the resin (119 um); non-absorbing particles.
run_ok mie_slurry mie --material "$materials/alumina-seed000.json" --json --plot "$work/phase.svg"
check "$work/mie_slurry.json" '(.x - 56.238387 | fabs) < 1e-5' '(.m[0] - 1.75 / 1.45 | fabs) < 1e-12' \
  '(.mua_per_mm - 1 / 0.119 | fabs) < 1e-9' '.qabs < 1e-9' '.mus_per_mm > 0' \
  '(.phase_table_mean_cosine - .g | fabs) < 1e-4'
check_files "$work/phase.svg"

# --- mc --------------------------------------------------------------------------------------------
expect_error "thickness" mc --material "$materials/vandehulst-slab.json" --photons 1000 --thickness -1mm --json
expect_error "'--photons': expected a whole number" mc --material "$materials/vandehulst-slab.json" --photons abc --json
expect_error "nonexistent.json: cannot read" mc --material "$data/nonexistent.json" --photons 1000 --json
# Van de Hulst's matched slab (mua 1/mm, mus 9/mm, g 0.75, optical thickness 2): Rd 0.09739,
# Tt 0.66096 (Prahl's MCML tables); 4 standard errors at 20000 photons.
run_ok mc mc --material "$materials/vandehulst-slab.json" --photons 20000 --seed 3 --thickness 0.2mm --json
check "$work/mc.json" '.photons == 20000' '.energy_balanced == true' \
  '(.diffuse_reflectance - 0.09739 | fabs) < 4 * .diffuse_reflectance_stderr' \
  '(.transmittance - 0.66096 | fabs) < 4 * .transmittance_stderr' \
  '.specular_reflectance == 0' \
  '(.diffuse_reflectance + .transmittance + .absorbed - 1 | fabs) < 1e-6'

# --- kernel ----------------------------------------------------------------------------------------
expect_no_output "$work/kernel_bad" kernel --material "$materials/alumina-seed000.json" --photons 2000 --w0 -5um --out "$work/kernel_bad" --json
expect_no_output "$work/kernel_bad" kernel --material "$data/nonexistent.json" --photons 2000 --out "$work/kernel_bad" --json
run_ok kernel kernel --material "$materials/alumina-seed000.json" --photons 20000 --out "$work/kernel" --json
# Scattering widens the beam (We3D > W0) and shortens its reach (De3D < 1/mua = 119 um); the
# specular reflection is Fresnel's ((1.45 - 1) / (1.45 + 1))^2 at normal incidence.
check "$work/kernel.json" '.W0_um == 50' '.We3D_um > .W0_um' '.De3D_um < .Dp_no_scattering_um' \
  '.De3D_um > 0' '(.Dp_no_scattering_um - 119 | fabs) < 1e-6' '.zmax_um >= 0' \
  '.monte_carlo.photons == 20000' '.monte_carlo.energy_balanced == true' \
  '(.monte_carlo.specular_reflectance - (0.45 / 2.45) * (0.45 / 2.45) | fabs) < 1e-6'
check "$work/kernel/kernel.json" '.photons == 20000' '.power_mW == 10'
check_files "$work/kernel/kernel.vdb" "$work/kernel/intensity_fit.png"

# --- part ------------------------------------------------------------------------------------------
expect_error "unknown test part 'nosuch'" part make nosuch --out "$work/nosuch.stl"
printf 'solid x\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n' >"$work/truncated.stl"
expect_error "truncated.stl:5: .*truncated" part check "$work/truncated.stl" --json
expect_error "missing.stl: cannot read" part check "$work/missing.stl" --json
# 0.25 mm high: exact in the STL's float32 coordinates, so its layers are exact too.
run_ok part_make part make l-shape --size 1mm --height 0.25mm --out "$work/l.stl" --json
# The L is a square less one quadrant: 0.75 x 1 mm^2 x 0.25 mm.
check "$work/part_make.json" '(.volume_mm3 - 0.1875 | fabs) < 1e-9' '.bounds_mm == [[-0.5, -0.5, 0], [0.5, 0.5, 0.25]]'
run_ok part_check part check "$work/l.stl" --json
check "$work/part_check.json" '.ok == true' '.open_edges == 0' '.non_manifold_edges == 0' \
  '.shells == 1' '(.volume_mm3 - 0.1875 | fabs) < 1e-6'
run_ok part_levelset part levelset "$work/l.stl" --voxel 50um --out "$work/l.vdb" --json
check "$work/part_levelset.json" '.voxel_mm == 0.05' '.active_voxels > 0'
check_files "$work/l.vdb"

# --- slice -----------------------------------------------------------------------------------------
expect_error "layer thickness must be positive" slice "$work/l.stl" --layer -1um --json
expect_error "missing.stl: cannot read" slice "$work/missing.stl" --json
run_ok slice slice "$work/l.stl" --layer 50um --out "$work/slices" --json
check "$work/slice.json" '.layer_count == 5' \
  '[.layers[].z] | . as $z | [range(5)] | all($z[.] - (0.025 + 0.05 * .) | fabs < 1e-9)' \
  '.layers | all((.area - 0.75 | fabs) < 1e-9 and (.perimeter - 4 | fabs) < 1e-9)' \
  '.layers | all(.outer_contours == 1 and .holes == 0)'
check_files "$work/slices/layer_00000.svg" "$work/slices/layer_00004_mask.png"

# --- calibrate -------------------------------------------------------------------------------------
printf 'dose_mJ_per_cm2,thickness_mm\n100,0.2\n200,x\n' >"$work/bad_wc.csv"
expect_error "bad_wc.csv:3: .*'x'" calibrate --working-curve "$work/bad_wc.csv"
expect_error "missing.csv: cannot read" calibrate --working-curve "$work/missing.csv" --json
# Jacobs' working curve Cd = Dp ln(E / Ec) fitted here by least squares of Cd on ln E.
read -r dp ec < <(awk -F, 'NR > 1 && $1 ~ /^[0-9.]+$/ { x = log($1); n++; sx += x; sy += $2;
  sxx += x * x; sxy += x * $2 } END { dp = (n * sxy - sx * sy) / (n * sxx - sx * sx);
  printf "%.12g %.12g\n", dp, exp((sx - sy / dp) / n) }' "$table1")
run_ok calibrate calibrate --working-curve "$table1" --gel-point 0.276 --json --plot "$work/wc.svg"
check "$work/calibrate.json" ".n_points == 15" "(.penetration_depth_mm / $dp - 1 | fabs) < 1e-6" \
  "(.critical_dose_mJ_per_cm2 / $ec - 1 | fabs) < 1e-6" \
  "(.K_cm2_per_mJ * .critical_dose_mJ_per_cm2 + (1 - 0.276 | log) | fabs) < 1e-6" \
  '.r_squared > 0.99' '.cure_model.model == "fpp"'
check_files "$work/wc.svg"

# --- run -------------------------------------------------------------------------------------------
# A cache of its own: the first run computes its kernel (`vpsim kernel` above may share the cache).
export VPSIM_CACHE_DIR="$work/run-cache"
expect_no_output "$work/run_bad" run "$data/bad_job_unknown_key.json" --out "$work/run_bad"
expect_error "bad_job_unknown_key.json: key 'simulation.voxl': unknown key" run "$data/bad_job_unknown_key.json" --out "$work/run_bad"
expect_no_output "$work/run_bad" run "$data/missing_job.json" --out "$work/run_bad"
run_ok run run "$data/small_job.json" --out "$work/run" --json
# 0.2 mm in 50 um layers; the part's volume; a cured part close to it; stdout is report.json.
check "$work/run.json" '.plan.layers == 4' '(.part.volume_mm3 - 0.15 | fabs) < 1e-9' \
  '.iou > 0.7 and .iou <= 1' '.kernel.photons == 20000' '.kernel.from_cache == false' \
  '.plan.energy_mJ > 0' '.surface_deviation_mm.rms > 0 and .surface_deviation_mm.rms < 0.05' \
  '(.cured_volume_mm3 / .part.volume_mm3 - 1 | fabs) < 0.3' '.aces.hatch_spacing_um > 0'
if ! cmp -s <(jq -S . "$work/run.json") <(jq -S . "$work/run/report.json"); then
  fail "run --json printed something else than report.json"
fi
check_files "$work/run/report.json" "$work/run/index.html" "$work/run/cured.stl" \
  "$work/run/plan.json" "$work/run/exposure.vdb"
# The exposure shaders run on every Vulkan device, lavapipe included: the exposure names the
# run's device, unless there is none (then both say "cpu").
check "$work/run.json" '.exposure.backend == .backend'
# The second run finds its kernel in the cache; --backend cpu takes the CPU loops.
run_ok run_cached run "$data/small_job.json" --out "$work/run_cached" --json --backend cpu
check "$work/run_cached.json" '.kernel.from_cache == true' '.exposure.backend == "cpu"' \
  '.backend == "cpu"'

# --- component listings: every key an object with name, default, dimension, doc ----------------
run_ok plan_list plan --list --json
check "$work/plan_list.json" 'map(.name) | index("aces") != null and index("inverse") != null' \
  'all(.[]; .keys | all(.[]; has("name") and has("default") and has("dimension") and has("doc")))' \
  '.[] | select(.name == "uniform-mask") | .keys[] | select(.name == "dose") | .default == "78 mJ/cm^2"'
run_ok components components --json
check "$work/components.json" '.cure_laws | map(.name) == ["fpp", "threshold"]' \
  '.exporters | map(.name) | index("cli") != null'
expect_error "key 'plan.homogenity': unknown key for planner 'aces'; did you mean 'homogeneity'" \
  run "$data/small_job.json" --out "$work/typo" --set plan.homogenity=0.02

# --- the memory budget: the CLI reads VPSIM_MEMORY_LIMIT into the run context (the library reads no
# environment); a malformed value is one error line naming it, whatever the command.
for limit in '5GB?' abc '5 G x' -1G 0 0M 5T; do
  VPSIM_MEMORY_LIMIT="$limit" expect_no_output "$work/mem_bad" run "$data/small_job.json" \
    --out "$work/mem_bad"
  VPSIM_MEMORY_LIMIT="$limit" expect_error "^vpsim: error: VPSIM_MEMORY_LIMIT: .*[(]a number of bytes with an optional K, M or G" \
    run "$data/small_job.json" --out "$work/mem_bad" --dry-run
done
VPSIM_MEMORY_LIMIT='5GB?' expect_error "^vpsim: error: VPSIM_MEMORY_LIMIT: unexpected text after the number .*, got '5GB[?]'" \
  mie --m 1.5 --x 1 --json
VPSIM_MEMORY_LIMIT=512M run_ok mem_512m run "$data/small_job.json" --out "$work/mem_dry" --dry-run --json
check "$work/mem_512m.json" '.budget_bytes == 536870912'
VPSIM_MEMORY_LIMIT=1073741824 run_ok mem_bytes plan "$data/small_job.json" --out "$work/mem_dry" --dry-run --json
check "$work/mem_bytes.json" '.budget_bytes == 1073741824'
run_ok mem_default run "$data/small_job.json" --out "$work/mem_dry" --dry-run --json
check "$work/mem_default.json" '.budget_bytes >= 268435456 and .budget_bytes <= 17179869184'
[[ -e "$work/mem_dry" ]] && fail "--dry-run wrote $work/mem_dry"
VPSIM_MEMORY_LIMIT=1K expect_error "allowed \(set by VPSIM_MEMORY_LIMIT\)" run "$data/small_job.json" \
  --out "$work/mem_small"
[[ -e "$work/mem_small" ]] && fail "a refused run wrote $work/mem_small"

if "$vpsim" export --help >/dev/null 2>&1; then
  expect_ok '"vectors": 24' export "$data/plan_two_parts.json" -o "$work/scan.cli" --json
  expect_ok '"proven_optimal": true' export "$data/plan_two_parts.json" -o "$work/scan_bin.cli" \
    --format binary --trajectories --machine "$data/machine_scanner.json" --json
  expect_error "machine_bad_scanner.json: key 'machine.scanner.process_speed'" export \
    "$data/plan_two_parts.json" -o "$work/bad.cli" --machine "$data/machine_bad_scanner.json"
  [[ -e "$work/bad.cli" ]] && { failed=$((failed + 1)); echo "FAILED: bad input wrote bad.cli"; }
  expect_error "missing_plan.json: cannot read" export "$data/missing_plan.json" -o "$work/x.cli"
  # The exporter by the file's extension; SL1 needs the projector's calibration and takes masks.
  expect_error "no exporter writes '.sl1' files.*sl1: .*grey_levels" export \
    "$data/plan_two_parts.json" -o "$work/x.sl1"
  expect_error "unknown key for exporter 'cli'; did you mean 'units'" export \
    "$data/plan_two_parts.json" -o "$work/y.cli" --option unit=2um
fi

echo "cli: $passed passed, $failed failed"
[[ $failed -eq 0 ]]
