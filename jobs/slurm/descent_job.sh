# shellcheck shell=bash
# Sourced by the job scripts (jobs/slurm/*.sbatch, jobs/mpirun_helix.sh) once
# they know the repository root, $root: the binary, the output directory's
# restart flag, the launcher and the signals that stop a run at a checkpoint.

# Open MPI refuses to run as root unless told; containers and CI run as root.
if [ "$(id -u)" -eq 0 ]; then
  export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
fi

# descent's exit status when a signal stopped it at a checkpoint (EX_TEMPFAIL):
# the same command with --restart continues.
readonly descent_stopped=75

# The binary, or a message that says how to get one.
descent_binary() {
  local bin=${DESCENT_BIN:-$root/build/src/app/descent}
  if [ ! -x "$bin" ]; then
    echo "descent job: no descent binary at $bin: build it (scripts/build.sh) or set DESCENT_BIN" >&2
    exit 1
  fi
  echo "$bin"
}

# The flag that makes a resubmitted or requeued job continue in DIR: --restart
# when DIR holds a checkpoint, else --overwrite, so that a run killed before its
# first checkpoint starts again in DIR instead of in DIR.1 (which the next
# resubmission would not look at).
restart_flag() {
  if [ -d "$1/checkpoint" ]; then echo --restart; else echo --overwrite; fi
}

# The command that starts $1 ranks of $2 cores each inside the allocation, in
# the array `launch`. Slurm's MpiDefault is often none, and Debian's Open MPI
# has no PMI1/PMI2 support: srun needs --mpi=pmix. Without the pmix plugin,
# Open MPI's own mpirun (which launches through Slurm) still starts them.
slurm_launcher() {
  local ranks=$1 cpus=$2
  # srun since Slurm 22.05 does not inherit the job's --cpus-per-task: without
  # it every rank is bound to one core and all its threads share that core.
  export SRUN_CPUS_PER_TASK=$cpus
  if [ -n "${DESCENT_SRUN_MPI:-}" ]; then
    launch=(srun "--mpi=$DESCENT_SRUN_MPI")
  elif srun --mpi=list 2>&1 | grep -qw pmix; then
    launch=(srun --mpi=pmix)
  elif command -v mpirun >/dev/null; then
    launch=(mpirun -n "$ranks" --map-by "slot:PE=$cpus" --bind-to core)
    return
  else
    echo "descent job: warning: srun has no pmix plugin and there is no mpirun;" \
      "trying srun with MpiDefault" >&2
    launch=(srun)
  fi
  launch+=(-n "$ranks" --cpus-per-task="$cpus" --cpu-bind=cores --kill-on-bad-exit=1)
}

# One OpenMP thread per core of the rank. Threads are pinned only where Slurm
# pins the rank: without a task plugin every rank's mask is the whole node, and
# pinned threads of all ranks would start on the same first cores.
slurm_threads() {
  export OMP_NUM_THREADS=$1
  if scontrol show config 2>/dev/null | grep -Eq '^TaskPlugin +=.*(affinity|cgroup)'; then
    export OMP_PROC_BIND=${OMP_PROC_BIND:-close} OMP_PLACES=${OMP_PLACES:-cores}
  fi
}

# Runs "$@" in the background and, on USR1, TERM or INT, sends it USR1, because
# `#SBATCH --signal=B:USR1` signals only this shell. descent stops alike on all
# three; USR1 is the one srun and mpirun pass on to the ranks and nothing more
# (srun takes a first INT as a status request, mpirun kills on TERM). Sets
# `stop_signal` to the signal this shell got and returns the command's status.
stop_signal=""
run_forwarding_signals() {
  "$@" &
  local pid=$! status forwarded signal
  for signal in USR1 TERM INT; do
    # shellcheck disable=SC2064  # $pid and $signal are meant to be fixed now
    trap "forwarded=1; stop_signal=$signal; kill -USR1 $pid 2>/dev/null || true" "$signal"
  done
  # A trapped signal ends `wait` early with 128 + its number while the ranks
  # are still writing their checkpoint: wait again until the command exits.
  while :; do
    forwarded=0
    status=0
    wait "$pid" || status=$?
    [ "$forwarded" = 1 ] || break
  done
  trap - USR1 TERM INT
  return "$status"
}

# An array element's output directory $1, recorded where the array's other
# elements record theirs: runs/array-ARRAYJOBID/TASKID holds its absolute
# path. jobs/slurm/scaling_table.sbatch tabulates exactly the directories of
# one array from there, whatever --array, --job-name or scene it ran with.
# Rewritten, not appended, so a requeued element leaves one line.
record_array_element() {
  [ -n "${SLURM_ARRAY_JOB_ID:-}" ] || return 0
  local list=runs/array-$SLURM_ARRAY_JOB_ID folder=$1
  [ "${folder#/}" != "$folder" ] || folder=$PWD/$folder
  mkdir -p "$list"
  echo "$folder" >"$list/${SLURM_ARRAY_TASK_ID:?}"
}

# A batch job's step: descent on $1 ranks of SLURM_CPUS_PER_TASK cores each,
# writing to directory $2, with `descent run` arguments "${@:3}" (the scene
# first). A run stopped by USR1 (the time limit is near, or `scancel
# --signal=USR1 --batch`) puts the job back in the queue, and the requeued job
# continues with --restart. TERM (a plain scancel) is someone ending the job:
# it is not requeued. Exits with descent's status.
run_batch_job() {
  local ranks=$1 out=$2
  shift 2
  local cpus=${SLURM_CPUS_PER_TASK:-1} bin status=0
  bin=$(descent_binary)
  slurm_threads "$cpus"
  slurm_launcher "$ranks" "$cpus"
  echo "descent job: ${SLURM_JOB_ID} (restart ${SLURM_RESTART_COUNT:-0}): $ranks rank(s) x $cpus core(s)" \
    "via ${launch[*]}, out $out"
  run_forwarding_signals "${launch[@]}" "$bin" run "$@" --out "$out" "$(restart_flag "$out")" ||
    status=$?
  if [ "$status" -ne "$descent_stopped" ]; then
    exit "$status"
  fi
  if [ "$stop_signal" != TERM ] && [ "$stop_signal" != INT ] &&
    scontrol requeue "$SLURM_JOB_ID"; then
    echo "descent job: stopped at a checkpoint in $out; job $SLURM_JOB_ID requeued to continue"
  else
    echo "descent job: stopped at a checkpoint in $out; submit the same job again to continue" >&2
  fi
  exit "$status"
}
