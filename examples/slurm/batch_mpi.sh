#!/bin/bash
# brdfit batch as one MPI job under Slurm: task 0 coordinates and owns the database, the
# other tasks fit (docs/batch.md, "MPI"). One task per worker plus one, each with its
# cores; data files and the manifest on a file system every node sees.
#
#   sbatch --ntasks=17 batch_mpi.sh library.json results.db
#
# Rerunning the same command after a failure resumes it.
#SBATCH --job-name=brdfit-mpi
#SBATCH --ntasks=9
#SBATCH --cpus-per-task=4
#SBATCH --output=slurm-%j.out
set -eu
exec srun --mpi=pmix brdfit batch "$1" -o "$2" --threads "${SLURM_CPUS_PER_TASK:-1}"
