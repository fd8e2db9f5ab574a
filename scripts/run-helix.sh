#!/usr/bin/env bash
# Installs dependencies, builds, and runs the main job: the generated double
# helix (~82K tets) on 2 MPI ranks for 60 frames, frames and stats in out/helix.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMP_NUM_THREADS=${OMP_NUM_THREADS:-1}
mpiexec -n 2 --oversubscribe build/src/app/descent run "$@"
