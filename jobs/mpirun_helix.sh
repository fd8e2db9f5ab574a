#!/usr/bin/env bash
# The double helix on P ranks with plain mpirun (no scheduler, or inside an
# allocation where Open MPI's mpirun launches through Slurm).
#   [MPIRUN_ARGS="--hostfile hosts ..."] jobs/mpirun_helix.sh [RANKS] [PRESET] [descent run options...]
# RANKS: default SLURM_NTASKS, else 2. PRESET: 41k, 82k, 158k, 316k (default
# 82k). MPIRUN_ARGS: extra mpirun options, split at whitespace; they replace
# the default binding (with OMP_NUM_THREADS > 1, that many cores per rank).
# DESCENT_BIN, DESCENT_OUT as in jobs/slurm/helix.sbatch; the output directory,
# runs/helix-PRESET-npRANKS by default, does not change between runs, so a run
# that a signal stopped (descent exits 75 after writing a checkpoint) continues
# with --restart when the same command is run again.
set -euo pipefail
root=${DESCENT_ROOT:-$(cd "$(dirname "$0")/.." && pwd)}
source "$root/jobs/slurm/descent_job.sh"

ranks=${SLURM_NTASKS:-2}
if [ $# -gt 0 ] && [[ $1 =~ ^[0-9]+$ ]]; then
  ranks=$1
  shift
fi
preset=82k
if [ $# -gt 0 ] && [ "${1#-}" = "$1" ]; then
  preset=$1
  shift
fi
export OMP_NUM_THREADS=${OMP_NUM_THREADS:-1}
read -r -a mpirun_args <<<"${MPIRUN_ARGS:-}"
if [ -z "${MPIRUN_ARGS:-}" ] && [ "$OMP_NUM_THREADS" -gt 1 ]; then
  # mpirun binds each rank to one core by default: its threads would share it.
  mpirun_args=(--map-by "slot:PE=$OMP_NUM_THREADS" --bind-to core)
fi
out=${DESCENT_OUT:-runs/helix-${preset}-np${ranks}}
bin=$(descent_binary)

status=0
run_forwarding_signals mpirun -n "$ranks" "${mpirun_args[@]}" "$bin" run "$root/jobs/helix.toml" \
  --set "mesh.helix.preset=\"${preset}\"" --out "$out" "$(restart_flag "$out")" "$@" || status=$?
if [ "$status" -eq "$descent_stopped" ]; then
  echo "mpirun_helix.sh: stopped at a checkpoint in $out; run the same command again to continue" >&2
fi
exit "$status"
