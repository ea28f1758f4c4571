#!/bin/bash
# Joins the shards batch_array.sh wrote, as a job that waits for the whole array:
#
#   array=$(sbatch --parsable --array=1-8 batch_array.sh library.json results)
#   sbatch --dependency=afterok:$array merge.sh results results.db
#SBATCH --job-name=brdfit-merge
#SBATCH --cpus-per-task=1
#SBATCH --output=slurm-%j.out
set -eu
exec brdfit merge "$1"/shard_*.db -o "$2"
