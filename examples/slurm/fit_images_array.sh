#!/bin/bash
# brdfit fit-images as a Slurm job array: array task I of N fits band I/N of the stack's
# rows into OUT/tile_I; fit_images_merge.sh puts the tiles together once every task has
# finished (docs/images.md, "Large stacks, tiles and job arrays"). Every tile starts from
# the same whole-image subsample, so the merged maps are those of one run. Give the array a
# contiguous range; options after OUT go to fit-images:
#
#   job=$(sbatch --parsable --array=1-8 fit_images_array.sh ball/ walter fits --share alpha)
#   sbatch --dependency=afterok:$job fit_images_merge.sh fits ball-fit
#
# A failed or cancelled task is rerun by submitting that index again (sbatch --array=5 ...).
#SBATCH --job-name=brdfit-fit-images
#SBATCH --cpus-per-task=4
#SBATCH --output=slurm-%A_%a.out
set -eu
stack=$1
model=$2
out=$3
shift 3
# Indices counted from the array's first one, so --array=0-7 works as 1-8 does.
i=$((SLURM_ARRAY_TASK_ID - SLURM_ARRAY_TASK_MIN + 1))
mkdir -p "$out"
exec brdfit fit-images "$stack" -m "$model" -o "$out/tile_$i" --tile "$i/$SLURM_ARRAY_TASK_COUNT" \
  --threads "${SLURM_CPUS_PER_TASK:-1}" -q "$@"
