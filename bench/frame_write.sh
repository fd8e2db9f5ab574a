#!/usr/bin/env bash
# Per-frame write time of FrameWriter, this tree's (one hyperslab per rank)
# against the point-selection writer of commit 6865353, on 2 ranks, for about
# 1M and 10M vertices numbered as a partitioned grid-ordered mesh gives
# (helix) and randomly permuted (shuffled). Each configuration writes FRAMES
# frames into a fresh file under SCRATCH; bench/frame_write_bench.cpp says
# what is timed. Runs every configuration RUNS times, interleaving old and
# new so that load from others on a shared machine hits both alike.
#
#   bench/frame_write.sh [BUILD_DIR]        # default build
#   RUNS=3 FRAMES=7 SIZES="1000000 10000000" NUMBERINGS="helix shuffled" \
#   SCRATCH=/tmp/descent_frame_write bench/frame_write.sh
#
# Writes bench/results/frame_write/frame_write.log (appends) and
# frame_write.csv (one line per run: writer, numbering, vertices, ranks,
# frames, open seconds, median frame seconds, scratch directory: a disk, or
# /dev/shm to take the disk out of the figure).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build}
runs=${RUNS:-3}
frames=${FRAMES:-7}
sizes=${SIZES:-"1000000 10000000"}
numberings=${NUMBERINGS:-"helix shuffled"}
scratch=${SCRATCH:-/tmp/descent_frame_write}
old_commit=6865353
old_tree=${OLD_TREE:-/tmp/descent_oldwriter}
out=$root/bench/results/frame_write
mkdir -p "$out" "$scratch"
log=$out/frame_write.log
csv=$out/frame_write.csv
[[ -f $csv ]] || echo "writer,numbering,vertices,ranks,frames,open_s,median_frame_s,scratch" >"$csv"

cmake --build "$build" --target frame_write_bench -j2 >/dev/null
new_bench=$build/tests/mpi/frame_write_bench

# Today's writer, from history: the same bench source compiled against it.
if [[ ! -d $old_tree ]]; then
  git -C "$root" worktree add --detach "$old_tree" "$old_commit" >/dev/null
fi
old_bench=$build/frame_write_bench_old
if [[ ! -x $old_bench || $root/bench/frame_write_bench.cpp -nt $old_bench ]]; then
  mpicxx -std=c++20 -O3 -DNDEBUG -DDESCENT_BENCH_OLD_WRITER -I"$old_tree/src" -I"$old_tree" \
    "$root/bench/frame_write_bench.cpp" "$old_tree/src/io/frame_writer.cpp" \
    $(pkg-config --cflags --libs hdf5-openmpi) -o "$old_bench"
fi

{
  echo "== $(date -Is) $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2) x $(nproc) cores"
  echo "new: $(git -C "$root" rev-parse --short HEAD) old: $old_commit; scratch: $scratch"
  echo "load: $(uptime)"
} >>"$log"
for run in $(seq "$runs"); do
  for vertices in $sizes; do
    for numbering in $numberings; do
      for writer in old new; do
        bench=$new_bench
        [[ $writer == old ]] && bench=$old_bench
        dir=$scratch/$writer-$numbering-$vertices
        rm -rf "$dir"
        echo "-- run $run: $writer $numbering $vertices; load: $(cut -d' ' -f1-3 /proc/loadavg)" >>"$log"
        OMP_NUM_THREADS=1 mpiexec -n 2 "$bench" --vertices "$vertices" --numbering "$numbering" \
          --frames "$frames" --out "$dir" | tee -a "$log" | grep '^writer=' |
          sed -E "s/[a-z_]+=//g; s/ /,/g; s|\$|,$scratch|" >>"$csv"
        rm -rf "$dir"
      done
    done
  done
done
tail -n "$((runs * $(wc -w <<<"$sizes") * $(wc -w <<<"$numberings") * 2))" "$csv"
