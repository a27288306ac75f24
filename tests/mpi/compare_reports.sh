# Sourced by tests/mpi/run_mpi_tests.sh and tests/cli/run_batch_tests.sh: report figures without
# what may differ between two runs of one job (timings, cache use, the run's paths and files,
# how the work was split).
# figures FILE: report.json's figures as canonical JSON.
figures() {
  jq -S 'del(.mpi, .stage_seconds, .files, .job)
         | del(.exposure.engine_seconds, .exposure.store_and_compare_seconds)
         | del(.kernel.from_cache)
         | walk(if type == "object" then with_entries(select(.key | test("seconds$") | not))
                else . end)' "$1"
}
