#!/usr/bin/env bash
# The double helix on P ranks with plain mpirun (no scheduler).
#   jobs/mpirun_helix.sh [RANKS] [PRESET] [extra descent run options...]
set -euo pipefail
ranks=${1:-2}
preset=${2:-82k}
shift $(( $# > 2 ? 2 : $# ))
export OMP_NUM_THREADS=${OMP_NUM_THREADS:-1}
mpirun -n "$ranks" build/src/app/descent run jobs/helix.toml \
  --set "mesh.helix.preset=\"${preset}\"" --out "runs/helix-${preset}-np${ranks}" "$@"
