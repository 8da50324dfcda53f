#!/usr/bin/env bash
# `acdf bench-error` as a Slurm array job: task K of an array 1-N renders shard K/N into
# OUT/shard-K; a job depending on the array merges them into OUT (results, images, plots).
#
#   jobid=$(sbatch --parsable --array=1-8 scripts/bench-error-slurm.sh OUT SCENE [bench-error options])
#   sbatch --dependency=afterok:$jobid --wrap "build/bin/acdf bench-error --merge OUT/shard-* --out OUT"
#
# Every node must see acdf, SCENE and OUT at the same paths. Give --reference REF.exr (one render
# for all shards): nodes of different CPUs can render the reference differently in the last bits,
# and the merge refuses shards measured against different references. Submit from the source tree
# (or set ACDF to the acdf program).
#SBATCH --job-name=acdf-bench-error
#SBATCH --cpus-per-task=8
#SBATCH --output=bench-error-%A_%a.log
set -euo pipefail

if (($# < 2)) || [[ -z ${SLURM_ARRAY_TASK_ID:-} ]]; then
  echo "usage: sbatch --array=1-N $0 OUT SCENE [bench-error options]" >&2
  exit 2
fi
out=$1 scene=$2
shift 2
acdf=${ACDF:-${SLURM_SUBMIT_DIR:-.}/build/bin/acdf}
n=${SLURM_ARRAY_TASK_MAX}
[[ ${SLURM_ARRAY_TASK_MIN} == 1 ]] || { echo "$0: the array must be 1-N" >&2; exit 2; }
mkdir -p "$out"
exec "$acdf" bench-error "$scene" --shard "$SLURM_ARRAY_TASK_ID/$n" --out "$out/shard-$SLURM_ARRAY_TASK_ID" \
  --no-plot --threads "${SLURM_CPUS_PER_TASK:-0}" "$@"
