#!/usr/bin/env bash
# Installs dependencies, builds, and runs the main job: the generated double
# helix (~82K tets) on 2 MPI ranks for 60 frames, frames and stats in out/helix.
# Extra arguments go to `descent run` (e.g. --set solver.iterations=64).
set -euo pipefail
source "$(dirname "$0")/common.sh"
mpiexec -n 2 --oversubscribe build/src/app/descent run "$@"
