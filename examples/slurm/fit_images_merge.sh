#!/bin/bash
# The merge after fit_images_array.sh: every OUT/tile_* folder into one output folder,
# as one run of the whole image writes it (brdfit merge-images refuses missing tiles and
# tiles of different runs). Submit it to wait for the array:
#
#   sbatch --dependency=afterok:$job fit_images_merge.sh fits ball-fit
#SBATCH --job-name=brdfit-fit-images-merge
#SBATCH --output=slurm-%j.out
set -eu
exec brdfit merge-images "$1"/tile_* -o "$2" -q
