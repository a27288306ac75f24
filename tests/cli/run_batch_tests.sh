#!/usr/bin/env bash
# `vpsim batch` in one process: jobs given as files and as a sweep file run into DIR/<name> with
# DIR/batch.json; each job's figures equal its own `vpsim run`; a failed job does not stop the
# others and makes the exit status non-zero; bad sweep files give one clear error line.
# Usage: run_batch_tests.sh VPSIM_BINARY SOURCE_DIR
set -uo pipefail
vpsim="$1"; source="$2"
die() { echo "batch: FAILED: $*"; exit 1; }
command -v jq >/dev/null || die "jq is missing (tools/debian-packages.txt)"
. "$source/tests/mpi/compare_reports.sh"
work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
export VPSIM_CACHE_DIR="$work/cache"
failed=0
fail() { failed=$((failed + 1)); echo "FAILED: $*"; }
job="$source/tests/cli/data/small_job.json"
few="--set kernel.photons=4000"

# A sweep of three runs, the second one broken (a misspelt key).
cat >"$work/sweep.json" <<JSON
{"job": "$job", "runs": [
  {"name": "dose-8", "set": ["cure.critical_dose=8 mJ/cm^2"]},
  {"name": "broken", "set": ["plan.homogenity=0.02"]},
  {"name": "dose-12", "set": ["cure.critical_dose=12 mJ/cm^2", "plan.homogeneity=0.02"]}]}
JSON
"$vpsim" -q batch --sweep "$work/sweep.json" --out "$work/sweep" $few >"$work/sweep.out" 2>"$work/sweep.err"
code=$?
[[ $code -ne 0 ]] || fail "a batch with a failed job exited 0"
grep -q "1 of 3 batch jobs failed (broken)" "$work/sweep.err" || fail "no summary line of the failure: $(cat "$work/sweep.err")"
jq -e '.failed == 1 and .succeeded == 2 and (.jobs | map(.status)) == ["ok", "failed", "ok"]
       and (.jobs[1].error | test("homogenity"))' "$work/sweep/batch.json" >/dev/null ||
  fail "batch.json statuses: $(jq -c '.jobs | map({name, status})' "$work/sweep/batch.json")"
[[ -f "$work/sweep/dose-12/report.json" ]] || fail "the job after the failed one did not run"
# Each job's figures equal `vpsim run` of the same job and overrides.
"$vpsim" -q run "$job" --out "$work/single" $few \
  --set "cure.critical_dose=12 mJ/cm^2" --set plan.homogeneity=0.02 >/dev/null 2>&1 || fail "vpsim run of dose-12"
[[ "$(figures "$work/single/report.json")" == "$(figures "$work/sweep/dose-12/report.json")" ]] ||
  fail "batch's dose-12 figures differ from vpsim run's"
[[ "$(jq -c .jobs[2].figures.iou "$work/sweep/batch.json")" == "$(jq -c .iou "$work/single/report.json")" ]] ||
  fail "batch.json's headline IoU differs from the job's report"

# Job files as given, each into DIR/<stem>.
"$vpsim" -q batch "$job" --out "$work/files" --json $few >"$work/files.json" 2>&1 ||
  fail "batch of one job file: $(cat "$work/files.json")"
jq -e '.jobs[0].name == "small_job" and .jobs[0].status == "ok" and .mpi.ranks == 1' "$work/files.json" >/dev/null ||
  fail "batch --json of a job file"
[[ -f "$work/files/small_job/report.json" ]] || fail "DIR/<stem>/report.json missing"

# Bad input: one error line naming the file and key, nothing run.
expect_error() {
  local pattern="$1"; shift
  "$vpsim" -q "$@" >"$work/out" 2>"$work/err"; local code=$?
  if [[ $code -eq 0 || $(wc -l <"$work/err") -ne 1 ]] || ! grep -qE -- "$pattern" "$work/err"; then
    fail "vpsim $* (exit $code, expected one line /$pattern/)"; cat "$work/err"
  fi
}
echo '{"job": "job.json", "runs": [{"name": "a", "sett": []}]}' >"$work/typo.json"
expect_error "typo.json: key 'runs\[0\].sett': unknown key" batch --sweep "$work/typo.json" --out "$work/x"
echo '{"job": "job.json", "runs": [{"name": "../up"}]}' >"$work/name.json"
expect_error "name.json: key 'runs\[0\].name'" batch --sweep "$work/name.json" --out "$work/x"
echo '{"job": "job.json", "runs": [{"name": "a"}, {"name": "a"}]}' >"$work/twice.json"
expect_error "twice.json: key 'runs': two jobs named 'a'" batch --sweep "$work/twice.json" --out "$work/x"
expect_error "give job files or --sweep" batch --out "$work/x"
[[ ! -e "$work/x" ]] || fail "a refused batch wrote its output directory"

[[ $failed -eq 0 ]] || { echo "batch: $failed check(s) FAILED"; exit 1; }
echo "batch: all checks passed"
