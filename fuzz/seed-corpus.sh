#!/usr/bin/env bash
# Rebuilds the seed corpora of the fuzz targets (fuzz/corpus/<target>/seed-*) from the files the
# repository ships: models, programs, scenarios, logs, OCSP examples and the malformed inputs of
# the snapshot tests. Run it from anywhere after changing those files; FUZZING.md explains the
# corpora.
set -euo pipefail
cd "$(dirname "$0")/.."
corpus=fuzz/corpus

# seed TARGET FILE...: copies each file to corpus/TARGET/seed-<path with / as _>.
seed() {
    local target=$1
    shift
    mkdir -p "$corpus/$target"
    for file in "$@"; do
        cp "$file" "$corpus/$target/seed-${file//\//_}"
    done
}

rm -f "$corpus"/*/seed-*
seed rmpl programs/*.rmpl tests/bad_input/rmpl_*.rmpl
seed plant models/*.ron tests/bad_models/*.ron
seed scenario scenarios/*/*.ron tests/bad_scenarios/*.ron tests/scenarios/*.ron
seed ocsp models/ocsp/*.ron tests/bad_input/ocsp_*.ron
seed estimation_log tests/logs/*.jsonl
seed mission missions/*.ron tests/missions/*.ron tests/bad_missions/*.ron
seed schedule missions/*.ron tests/missions/*.ron tests/bad_missions/*.ron
seed mission_scenario scenarios/thermostat/*.ron scenarios/rover/mission_*.ron scenarios/mars_edl/descent_mission.ron
seed protocol scenarios/rover/r*.ron tests/bad_rover/*.ron

# The constraint language has no files of its own: its seeds are the formulas written in the
# models and scenarios (every quoted string with a comparison in it) and the programs'
# conditions and goals (between braces), one formula per file.
mkdir -p "$corpus/constraint"
{
    grep -ohE '"[^"]*(=|<|>)[^"]*"' models/*.ron models/ocsp/*.ron scenarios/*/*.ron | sed 's/^"//; s/"$//'
    grep -ohE '\{[^{}]*\}' programs/*.rmpl | sed 's/^{//; s/}$//'
} | sed 's/^ *//; s/ *$//' | grep -v '^$' | sort -u | {
    n=0
    while IFS= read -r formula; do
        n=$((n + 1))
        printf '%s' "$formula" > "$corpus/constraint/seed-formula-$n"
    done
}
du -sh "$corpus"
