#!/usr/bin/env bash
# What contact with obstacles costs (docs/contact.md), in three parts, each
# configuration run RUNS times with old and new interleaved so that load
# from others on a shared machine hits both alike:
#   1. nothing for scenes without obstacles: the helix (PRESET, FRAMES
#      frames, 1 rank) with this tree's binary and with the binary of
#      OLD_COMMIT (the tree before contact): frames.h5 compared value for
#      value, and ms per frame side by side;
#   2. an obstacle that never touches (a floor 10 m below): the cost of the
#      contact pass, guard and the guess's allreduce when nothing touches;
#   3. jobs/contact/helix_floor.toml at PRESET on 1 and 2 ranks: the helix
#      let go onto a floor, ms per frame and iterations, against the same
#      helix falling freely (no floor) over the same frames.
#
#   bench/contact_cost.sh [BUILD_DIR]
#   RUNS=3 FRAMES=20 PRESET=41k OLD_COMMIT=1dedf88 bench/contact_cost.sh
#
# Writes bench/results/contact/contact_cost.csv (one line per run) and
# contact_cost.log (the machine, the commands, the medians).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build}
runs=${RUNS:-3}
frames=${FRAMES:-20}
preset=${PRESET:-41k}
old_commit=${OLD_COMMIT:-1dedf88}
old_tree=${OLD_TREE:-/tmp/descent_before_contact}
scratch=${SCRATCH:-/tmp/descent_contact_cost}
python=${PYTHON:-/usr/bin/python3}
out=$root/bench/results/contact
mkdir -p "$out" "$scratch"
log=$out/contact_cost.log
csv=$out/contact_cost.csv
echo "case,binary,ranks,run,frames,ms_per_frame,iterations" >"$csv"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMP_NUM_THREADS=1

cmake --build "$build" --target descent -j2 >/dev/null
new_bin=$build/src/app/descent
if [[ ! -d $old_tree ]]; then
  git -C "$root" worktree add --detach "$old_tree" "$old_commit" >/dev/null
fi
if [[ ! -x $old_tree/build/src/app/descent ]]; then
  cmake -S "$old_tree" -B "$old_tree/build" -DCMAKE_BUILD_TYPE=Release -DDESCENT_BUILD_TESTS=OFF \
    -DDESCENT_ENABLE_CUDA=OFF >/dev/null
  cmake --build "$old_tree/build" --target descent -j2 >/dev/null
fi
old_bin=$old_tree/build/src/app/descent

{
  echo "== $(date -u +%FT%TZ) contact cost"
  echo "machine: $(lscpu | sed -n 's/^Model name: *//p'), $(nproc --all) cores; no GPU used"
  echo "new: $(git -C "$root" rev-parse --short HEAD) (+ working tree), old: $old_commit"
  echo "runs $runs, frames $frames, helix preset $preset, OMP_NUM_THREADS=1"
} | tee -a "$log"

# run NAME BINARY RANKS RUN SCENE [--set ...]: one run into $scratch/NAME.b.r.k
run() {
  local name=$1 bin=$2 ranks=$3 k=$4 scene=$5
  shift 5
  local tag=$([[ $bin == "$old_bin" ]] && echo old || echo new)
  local dir=$scratch/$name.$tag.$ranks.$k
  rm -rf "$dir"
  mpiexec --oversubscribe -n "$ranks" "$bin" run "$scene" --quiet --set "output.dir=\"$dir\"" \
    --set "time.frames=$frames" --set "mesh.helix.preset=\"$preset\"" "$@" >/dev/null
  "$python" - "$dir/stats.csv" "$name" "$tag" "$ranks" "$k" "$frames" >>"$csv" <<'EOF'
import csv, statistics, sys
rows = list(csv.DictReader(open(sys.argv[1])))
ms = [float(r["wall_ms"]) for r in rows]
its = sum(int(r["iterations"]) for r in rows)
print(",".join(sys.argv[2:7] + [f"{statistics.mean(ms):.1f}", str(its)]))
EOF
}

helix=$root/jobs/helix.toml
floor=$root/jobs/contact/helix_floor.toml
# The main job with a floor 10 m below it; the floor scene without its floor.
far=$scratch/helix_far_floor.toml
fall=$scratch/helix_fall.toml
{
  cat "$helix"
  printf '\n[[obstacle]]\nkind = "plane"\npoint = [0.0, -10.0, 0.0]\nnormal = [0.0, 1.0, 0.0]\n'
} >"$far"
sed '/^\[\[obstacle\]\]/,/^friction/d' "$floor" >"$fall"
grep -q obstacle "$fall" && { echo "could not remove the floor from $floor" >&2; exit 1; }
for k in $(seq 1 "$runs"); do
  run main "$old_bin" 1 "$k" "$helix"
  run main "$new_bin" 1 "$k" "$helix"
  run far_floor "$new_bin" 1 "$k" "$far"
  for ranks in 1 2; do
    run helix_floor "$new_bin" "$ranks" "$k" "$floor"
    run helix_fall "$new_bin" "$ranks" "$k" "$fall"
  done
done

# 1: the same values, bit for bit (every dataset of every frame).
"$python" - "$scratch/main.old.1.1/frames.h5" "$scratch/main.new.1.1/frames.h5" <<'EOF' | tee -a "$log"
import h5py, numpy as np, sys
a, b = h5py.File(sys.argv[1]), h5py.File(sys.argv[2])
names = []
a.visit(lambda n: names.append(n) if isinstance(a[n], h5py.Dataset) else None)
same = all(np.array_equal(a[n][()], b[n][()]) for n in names)
print(f"no obstacles: frames.h5 of old and new {'identical' if same else 'DIFFER'} "
      f"in all {len(names)} datasets")
EOF
"$python" - "$csv" <<'EOF' | tee -a "$log"
import csv, statistics, sys
rows = list(csv.DictReader(open(sys.argv[1])))
groups = {}
for r in rows:
    groups.setdefault((r["case"], r["binary"], r["ranks"]), []).append(r)
for (case, binary, ranks), rs in groups.items():
    ms = statistics.median(float(r["ms_per_frame"]) for r in rs)
    its = statistics.median(int(r["iterations"]) for r in rs)
    print(f"{case:12s} {binary} {ranks} rank(s): median {ms:8.1f} ms/frame, "
          f"{its} iterations over the frames ({len(rs)} runs)")
EOF
