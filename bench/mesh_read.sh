#!/usr/bin/env bash
# Reading the ~4M-tet double helix (resolution 11.35) into every rank's
# MeshSlice on 2 ranks: from .h5 (read_mesh_h5: each rank reads its blocks)
# against .msh (read_mesh_slice on a Gmsh 2.2 file from write_mesh: rank 0
# parses and validates it all, then scatters). Wall time of the slowest rank
# and peak RSS per rank; one read per process, RUNS times each, alternating.
#
#   bench/mesh_read.sh [BUILD_DIR]          # default build
#   RUNS=3 RESOLUTION=11.35 RANKS=2 SCRATCH=/tmp/descent_mesh_read bench/mesh_read.sh
#
# The two files are written once under SCRATCH and kept for later runs; no
# cache is dropped (a shared machine), so reads may find them in the page
# cache. Appends to bench/results/mesh_read/mesh_read.log.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build}
runs=${RUNS:-3}
resolution=${RESOLUTION:-11.35}
ranks=${RANKS:-2}
scratch=${SCRATCH:-/tmp/descent_mesh_read}/helix_$resolution
out=$root/bench/results/mesh_read
mkdir -p "$out"
log=$out/mesh_read.log

cmake --build "$build" --target mesh_read_bench -j2 >/dev/null
bench=$build/tests/mpi/mesh_read_bench
if [[ ! -f $scratch/helix.h5 || ! -f $scratch/helix.msh ]]; then
  mpiexec -n 1 "$bench" prepare "$resolution" "$scratch" | tee -a "$log"
fi

{
  echo "== $(date -Is) $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2) x $(nproc) cores"
  echo "commit $(git -C "$root" rev-parse --short HEAD); load: $(uptime)"
  ls -l "$scratch"
} >>"$log"
for run in $(seq "$runs"); do
  for file in helix.h5 helix.msh; do
    echo "-- run $run: $file; load: $(cut -d' ' -f1-3 /proc/loadavg)" >>"$log"
    OMP_NUM_THREADS=1 mpiexec -n "$ranks" "$bench" read "$scratch/$file" | tee -a "$log"
  done
done
