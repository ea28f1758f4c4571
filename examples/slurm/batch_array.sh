#!/bin/bash
# brdfit batch as a Slurm job array: array task I of N runs share I/N of a manifest's items
# into its own database, OUT/shard_I.db; brdfit merge joins the shards once every task has
# finished (docs/batch.md, "Shards and merging"). Give the array a contiguous range:
#
#   sbatch --array=1-8 batch_array.sh library.json results
#   brdfit merge results/shard_*.db -o results.db       # after the array (or: merge.sh)
#
# A task that fails or is cancelled is resumed by submitting that index again
# (sbatch --array=5 ...): it skips the items its database already holds.
#SBATCH --job-name=brdfit-batch
#SBATCH --cpus-per-task=4
#SBATCH --output=slurm-%A_%a.out
set -eu
manifest=$1
out=${2:-.}
# Indices counted from the array's first one, so --array=0-7 works as 1-8 does.
i=$((SLURM_ARRAY_TASK_ID - SLURM_ARRAY_TASK_MIN + 1))
mkdir -p "$out"
exec brdfit batch "$manifest" -o "$out/shard_$i.db" --shard "$i/$SLURM_ARRAY_TASK_COUNT" \
  --threads "${SLURM_CPUS_PER_TASK:-1}"
