#!/usr/bin/env bash
# End-to-end checks of the vpsim CLI: bad input gives exactly one clear line on stderr naming the
# file/key and the reason, a non-zero exit code, and nothing on stdout; good input succeeds.
# Usage: run_cli_tests.sh VPSIM_BINARY DATA_DIR SOURCE_DIR
set -uo pipefail
vpsim="$1"; data="$2"; source="$3"
work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
passed=0; failed=0

# expect_error PATTERN ARGS...: fails unless exit != 0, stdout empty, stderr one line matching PATTERN.
expect_error() {
  local pattern="$1"; shift
  "$vpsim" -q "$@" >"$work/out" 2>"$work/err"; local code=$?
  local lines; lines=$(wc -l <"$work/err")
  if [[ $code -ne 0 && ! -s "$work/out" && $lines -eq 1 ]] && grep -qE "$pattern" "$work/err"; then
    passed=$((passed + 1))
  else
    failed=$((failed + 1))
    echo "FAILED: vpsim $* (exit $code, $lines stderr lines, expected /$pattern/)"; cat "$work/err" "$work/out"
  fi
}

# expect_ok PATTERN ARGS...: exit 0 and stdout matching PATTERN.
expect_ok() {
  local pattern="$1"; shift
  "$vpsim" -q "$@" >"$work/out" 2>"$work/err"; local code=$?
  if [[ $code -eq 0 ]] && grep -qE "$pattern" "$work/out"; then
    passed=$((passed + 1))
  else
    failed=$((failed + 1))
    echo "FAILED: vpsim $* (exit $code, expected /$pattern/ on stdout)"; cat "$work/err" "$work/out"
  fi
}

expect_ok '"name": "llvmpipe' devices --json
expect_ok 'vpsim [0-9]' --version
expect_error "backend" --backend cuda devices

if "$vpsim" mie --help >/dev/null 2>&1; then
  expect_error "unknown_key.json: key 'particles.radus': unknown key" mie --material "$data/unknown_key.json" --json
  expect_error "wrong_unit.json: key 'particles.radius': expected length" mie --material "$data/wrong_unit.json" --json
  expect_error "malformed.json:3: malformed JSON" mie --material "$data/malformed.json" --json
  expect_error "missing.json: cannot read" mie --material "$data/missing.json" --json
  expect_ok '"qext"' mie --m 1.5-0.1i --x 10 --angles 0,140,180 --json
fi

if "$vpsim" calibrate --help >/dev/null 2>&1; then
  table1="$source/tests/data/reference/seed001_table1_working_curve.csv"
  if [[ -f "$table1" ]]; then
    expect_ok '"penetration_depth_mm": 0.3659' calibrate --working-curve "$table1" --gel-point 0.276 --json
  fi
  printf 'dose_mJ_per_cm2,thickness_mm\n100,0.2\n200,x\n' > "$work/bad_wc.csv"
  expect_error "bad_wc.csv:3: .*'x'" calibrate --working-curve "$work/bad_wc.csv"
fi

if "$vpsim" export --help >/dev/null 2>&1; then
  expect_ok '"vectors": 24' export "$data/plan_two_parts.json" -o "$work/scan.cli" --json
  expect_ok '"proven_optimal": true' export "$data/plan_two_parts.json" -o "$work/scan_bin.cli" \
    --format binary --trajectories --machine "$data/machine_scanner.json" --json
  expect_error "machine_bad_scanner.json: key 'machine.scanner.process_speed'" export \
    "$data/plan_two_parts.json" -o "$work/bad.cli" --machine "$data/machine_bad_scanner.json"
  [[ -e "$work/bad.cli" ]] && { failed=$((failed + 1)); echo "FAILED: bad input wrote bad.cli"; }
  expect_error "missing_plan.json: cannot read" export "$data/missing_plan.json" -o "$work/x.cli"
fi

echo "cli: $passed passed, $failed failed"
[[ $failed -eq 0 ]]
