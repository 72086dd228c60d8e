#!/usr/bin/env bash
# Runs every fuzz target in turn for SECONDS each (default 60), one process at a time, and prints
# a line per target: executions, seconds, corpus files, findings. New inputs go to
# fuzz/work/<target>/ (not committed); the committed seeds in fuzz/corpus/<target>/ are read.
# Usage: fuzz/run-all.sh [SECONDS] [TARGET...]   (FUZZING.md has the details)
# FUZZ_ARGS adds libFuzzer flags (e.g. FUZZ_ARGS=-max_len=100000 for deep nesting).
set -uo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
shift || true
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
    targets=(constraint rmpl plant scenario ocsp estimation_log executive mission schedule mission_scenario protocol)
fi
export RUSTC_BOOTSTRAP=1 # cargo fuzz passes nightly-only flags; only the stable toolchain is installed
mkdir -p fuzz/work/logs
for target in "${targets[@]}"; do
    mkdir -p "fuzz/work/$target" "fuzz/corpus/$target"
    log="fuzz/work/logs/$target.log"
    nice -n 10 cargo fuzz run -s none "$target" "fuzz/work/$target" "fuzz/corpus/$target" -- \
        -max_total_time="$seconds" -rss_limit_mb=2048 -timeout=10 -print_final_stats=1 ${FUZZ_ARGS:-} \
        >"$log" 2>&1
    status=$?
    runs=$(grep -oE 'stat::number_of_executed_units: *[0-9]+' "$log" | grep -oE '[0-9]+$' | tail -1)
    files=$(find "fuzz/work/$target" -type f | wc -l)
    findings=$(find "fuzz/artifacts/$target" -type f 2>/dev/null | wc -l)
    echo "$target: exit $status, ${runs:-?} executions in ${seconds} s, $files new corpus files, $findings artifacts"
done
