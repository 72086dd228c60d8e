#!/bin/bash
# Submits a kairos campaign or exploration to Slurm as a job array of shards and a dependent
# merge job (docs/campaigns.md, "On a cluster"), and prints the two job ids.
#
#   scripts/slurm/submit.sh [--tasks N] [--cpus C] [--time T] [--partition P] OUT -- KIND ARGS...
#
#   KIND ARGS   `campaign SCENARIO --runs R --seed S ...` or `explore SCENARIO --faults F ...`
#               (not --shard, --out or --jobs: each task gets shard i/N, OUT/shard-i, and C
#               threads)
#   --tasks N   array tasks, one shard each (default 4)
#   --cpus C    CPUs per task (default 1)
#   --time T    each task's time limit, Slurm's format (default 02:00:00)
#   OUT         a directory every node can write: OUT/shard-i/, OUT/merged/, OUT/merged.txt,
#               OUT/merged.status, OUT/logs/
# The kairos binary is $KAIROS, or `kairos` on the PATH of the nodes. Other sbatch options
# (an account, a QOS) come from the SBATCH_* environment variables sbatch reads.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
tasks=4
cpus=1
time=02:00:00
partition=()
while [ $# -gt 0 ]; do
    case "$1" in
        --tasks) tasks=$2; shift 2 ;;
        --cpus) cpus=$2; shift 2 ;;
        --time) time=$2; shift 2 ;;
        --partition) partition=(--partition "$2"); shift 2 ;;
        --) shift; break ;;
        -*) echo "submit.sh: unknown option $1" >&2; exit 2 ;;
        *) out=$1; shift ;;
    esac
done
if [ -z "${out:-}" ] || [ $# -lt 2 ]; then
    sed -n '2,18p' "$0" | sed 's/^# \{0,1\}//' >&2
    exit 2
fi
kind=$1
shift
case "$kind" in campaign | explore) ;; *) echo "submit.sh: KIND is campaign or explore, not $kind" >&2; exit 2 ;; esac
if ! [[ "$tasks" =~ ^[1-9][0-9]*$ ]]; then echo "submit.sh: --tasks $tasks is not a count of tasks" >&2; exit 2; fi
mkdir -p "$out/logs"
out=$(cd "$out" && pwd)
array=$(sbatch --parsable "${partition[@]}" --array="0-$((tasks - 1))" --cpus-per-task="$cpus" \
    --time="$time" --output="$out/logs/shard-%a.log" \
    "$here/shard.sbatch" "$out" "$tasks" "$kind" "$@")
array=${array%%;*}
merge=$(sbatch --parsable "${partition[@]}" --dependency="afterany:$array" --time="$time" \
    --output="$out/logs/merge.log" "$here/merge.sbatch" "$out" "$tasks" "$kind")
merge=${merge%%;*}
echo "array $array merge $merge"
