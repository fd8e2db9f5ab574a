#!/usr/bin/env bash
# What the checkpoint checksum (XXH64, src/common/xxhash64.hpp) adds to the
# time of writing and syncing a checkpoint of the 1M-tet helix (one rank's
# file of the whole mesh: 200,480 vertices, 1,031,208 tets with
# interpolants, 22 MB); bench/checkpoint_write_bench.cpp says what is timed.
#
#   bench/checkpoint_write.sh [BUILD_DIR]            # default build
#   RUNS=41 SCRATCH=/tmp/descent_checkpoint_bench bench/checkpoint_write.sh
#
# Appends the machine, the command and every run to
# bench/results/checkpoint_write/checkpoint_write.log.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build}
runs=${RUNS:-41}
scratch=${SCRATCH:-/tmp/descent_checkpoint_bench}
out=$root/bench/results/checkpoint_write
mkdir -p "$out"
cmake --build "$build" --target checkpoint_write_bench -j2 >/dev/null
bench=$build/tests/mpi/checkpoint_write_bench
command="$bench --runs $runs --out $scratch"
{
  echo "== $(date -Is) $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2) x $(nproc) cores;" \
    "scratch $scratch on $(df -P "$(dirname "$scratch")" | awk 'NR == 2 {print $1}')" \
    "($(stat -f -c %T "$(dirname "$scratch")")); commit $(git -C "$root" rev-parse --short HEAD)"
  echo "\$ ${command#"$root"/}"  # the binary relative to the tree, not this machine's path
  $command
} | tee -a "$out/checkpoint_write.log"
