#!/usr/bin/env bash
# brdfit batch under a real Slurm (Debian's slurmctld, slurmd and munge; scripts/setup.sh
# installs them): a one-node cluster of this machine's own, started in the test's folder
# on ports of its own, runs the example job scripts of examples/slurm as a user would
# submit them: the job array (3 shards, one database each) and the merge job that waits
# for it (--dependency), whose result has the rows of a one-process run; the MPI job
# (srun --mpi=pmix, 3 tasks), the same rows again; and fit-images as an array of 3 tiles
# with its merge job, whose maps are those of a one-process fit. Needs root (CI runs as root): slurmd
# starts the jobs' processes.
set -u
source "$(dirname "$0")/common_cli.sh" "$@"
need hostname hostname; need munged munge; need mungekey munge; need slurmctld slurmctld; need slurmd slurmd; need sbatch slurm-client; need srun slurm-client; need squeue slurm-client; need sinfo slurm-client
source "$(dirname "$0")/batch_common.sh"
examples=$(cd "$(dirname "$0")/../examples/slurm" && pwd)
[ "$(id -u)" = 0 ] || { bad "slurmd must run as root to start jobs (CI runs as root)"; finish; exit 1; }

# As in cli_batch_mpi.sh: LeakSanitizer would report Open MPI's exit-time memory in the
# sanitizer build (the batch code itself is leak-checked by cli_batch.sh).
export ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0"

# --- the cluster: munge with its own key and socket, a controller and one node ---------------
cluster=$tmp/slurm
mkdir -p "$cluster/state" "$cluster/spool"
chmod 700 "$cluster"
# Ports of this run's own (two runs at once on one machine must not meet).
port=$((20000 + ($$ % 10000) * 2))
stop_cluster() {
  for d in slurmd slurmctld munged; do
    [ -f "$cluster/$d.pid" ] && kill "$(cat "$cluster/$d.pid")" 2>/dev/null
  done
  sleep 0.5
}
trap 'stop_cluster; chmod -R u+w "$tmp" 2>/dev/null; rm -rf "$tmp"' EXIT
mungekey --create --keyfile="$cluster/munge.key" 2>"$tmp/err" || bad "mungekey: $(cat "$tmp/err")"
munged --force --socket="$cluster/munge.sock" --key-file="$cluster/munge.key" --pid-file="$cluster/munged.pid" \
  --log-file="$cluster/munged.log" --seed-file="$cluster/munge.seed" 2>"$tmp/err" || bad "munged: $(cat "$tmp/err")"
cat > "$cluster/slurm.conf" <<CONF
ClusterName=brdfit$$
SlurmctldHost=$(hostname -s)(127.0.0.1)
SlurmctldPort=$port
SlurmdPort=$((port + 1))
AuthType=auth/munge
AuthInfo=socket=$cluster/munge.sock
CredType=cred/munge
SlurmUser=root
SlurmdUser=root
StateSaveLocation=$cluster/state
SlurmdSpoolDir=$cluster/spool
SlurmctldPidFile=$cluster/slurmctld.pid
SlurmdPidFile=$cluster/slurmd.pid
SlurmctldLogFile=$cluster/slurmctld.log
SlurmdLogFile=$cluster/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SchedulerType=sched/builtin
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
MpiDefault=none
NodeName=brdfitnode NodeAddr=127.0.0.1 CPUs=$(nproc) State=UNKNOWN
PartitionName=test Nodes=ALL Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF=$cluster/slurm.conf
slurmctld -f "$SLURM_CONF" && slurmd -f "$SLURM_CONF" -N brdfitnode || bad "the Slurm daemons did not start"
for _ in $(seq 100); do
  [ "$(sinfo -h -o %t 2>/dev/null)" = idle ] && break
  sleep 0.2
done
[ "$(sinfo -h -o %t 2>/dev/null)" = idle ] && ok ||
  { bad "the node is not idle: $(sinfo 2>&1 | tail -2; tail -n 3 "$cluster/slurmctld.log" "$cluster/slurmd.log")"; finish; exit 1; }

# --- the manifest, and a one-process run for reference ----------------------------------------
batch_manifest "" 3000
"$BRDFIT" batch "$tmp/m.json" -o "$tmp/one.db" || bad "one-process batch"
rows "$tmp/one.db" > "$tmp/one.rows"
# The jobs find brdfit on PATH, as a user's would (sbatch passes the environment on).
mkdir -p "$tmp/bin"
ln -s "$(cd "$(dirname "$BRDFIT")" && pwd)/$(basename "$BRDFIT")" "$tmp/bin/brdfit"
export PATH=$tmp/bin:$PATH
cd "$tmp"

# Waits (up to 3 minutes) until job $1 has left the queue.
wait_job() {
  for _ in $(seq 900); do
    [ -z "$(squeue -h -j "$1" 2>/dev/null)" ] && return 0
    sleep 0.2
  done
  return 1
}
# A job's state and exit code (each task's, for an array): "JobState=X ExitCode=N:S ...".
job_state() { scontrol -o show job "$1" 2>/dev/null | grep -o 'JobState=[A-Z]*\|ExitCode=[0-9:]*' | tr '\n' ' '; }

# --- the job array and the merge job that depends on it ---------------------------------------
array=$(sbatch --parsable --array=1-3 --cpus-per-task=1 "$examples/batch_array.sh" m.json shards 2>"$tmp/err") ||
  bad "sbatch of the array: $(cat "$tmp/err")"
merge=$(sbatch --parsable --dependency=afterok:"$array" "$examples/merge.sh" shards all.db 2>"$tmp/err") ||
  bad "sbatch of the merge: $(cat "$tmp/err")"
wait_job "$array" && wait_job "$merge" && ok || bad "the jobs did not finish in 3 minutes"
[ "$(job_state "$array")" = "$(printf 'JobState=COMPLETED ExitCode=0:0 %.0s' 1 2 3)" ] &&
  [ "$(job_state "$merge")" = "JobState=COMPLETED ExitCode=0:0 " ] && ok ||
  bad "array: $(job_state "$array"), merge: $(job_state "$merge")"
[ "$(ls shards)" = "$(printf 'shard_1.db\nshard_2.db\nshard_3.db')" ] && ok || bad "shards: $(ls shards) $(cat slurm-*.out)"
for k in 1 2 3; do
  [ "$(count "shards/shard_$k.db" "SELECT value FROM meta WHERE key = 'shard'")" = "$k/3" ] && ok || bad "shard_$k.db is not shard $k/3"
done
[ -f all.db ] && rows all.db | cmp -s - "$tmp/one.rows" && ok ||
  bad "merged array rows differ from one process (array: $(job_state "$array"), merge: $(job_state "$merge")): $(cat slurm-*.out | head -5)"

# --- the MPI job: srun --mpi=pmix, 3 tasks ------------------------------------------------------
job=$(sbatch --parsable --ntasks=3 --cpus-per-task=1 --overcommit "$examples/batch_mpi.sh" m.json mpi.db 2>"$tmp/err") ||
  bad "sbatch of the MPI job: $(cat "$tmp/err")"
wait_job "$job" && ok || bad "the MPI job did not finish in 3 minutes"
[ -f mpi.db ] && rows mpi.db | cmp -s - "$tmp/one.rows" && ok ||
  bad "MPI job rows differ from one process ($(job_state "$job")): $(cat "slurm-$job.out" | head -5)"
# Three tasks and one database: had they not been one MPI job, two would have been refused
# the database (locked by another batch) and the job would have failed.
[ "$(job_state "$job")" = "JobState=COMPLETED ExitCode=0:0 " ] && ok || bad "MPI job: $(job_state "$job")"
[ ! -s "slurm-$job.out" ] && ok || bad "MPI job not quiet: $(head -c 600 "slurm-$job.out")"

# --- fit-images: an array of tiles and the merge that waits for it -------------------------------
need idiff openimageio-tools; need jq jq
[ -x "$MAKE_STACK" ] || { bad "make_stack (the fifth argument) is missing"; finish; exit 1; }
"$MAKE_STACK" --model walter --params 'rho_d=0.5:0.35:0.2,rho_s=0.3:0.3:0.3,alpha=0.15,f0=0.04' --shape sphere \
  --size 40 --lights ring12 --noise 0.005 -o stack >/dev/null 2>"$tmp/err" || bad "make_stack: $(cat "$tmp/err")"
"$BRDFIT" fit-images stack -m walter -o whole -q || bad "one-process fit-images"
fa=$(sbatch --parsable --array=1-3 --cpus-per-task=1 "$examples/fit_images_array.sh" stack walter tiles 2>"$tmp/err") ||
  bad "sbatch of the fit-images array: $(cat "$tmp/err")"
fm=$(sbatch --parsable --dependency=afterok:"$fa" "$examples/fit_images_merge.sh" tiles merged 2>"$tmp/err") ||
  bad "sbatch of the fit-images merge: $(cat "$tmp/err")"
wait_job "$fa" && wait_job "$fm" && ok || bad "the fit-images jobs did not finish in 3 minutes"
[ "$(job_state "$fm")" = "JobState=COMPLETED ExitCode=0:0 " ] && ok ||
  bad "fit-images array: $(job_state "$fa"), merge: $(job_state "$fm"): $(cat slurm-*.out | tail -5)"
[ "$(ls tiles)" = "$(printf 'tile_1\ntile_2\ntile_3')" ] && ok || bad "tiles: $(ls tiles)"
for f in normals.exr rho_d.exr alpha.exr error.exr; do
  idiff -q "whole/$f" "merged/$f" >/dev/null 2>&1 && ok || bad "merged $f differs from the one-process fit"
done
[ "$(jq .counts merged/fit.json)" = "$(jq .counts whole/fit.json)" ] && ok || bad "merged counts differ"
finish
