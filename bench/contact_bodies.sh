#!/usr/bin/env bash
# What contact between bodies costs (docs/contact.md, Contact between
# bodies): jobs/contact/{bodies_floor,snowman,bowling,pile}.toml for FRAMES
# frames on 1 and 2 ranks, each RUNS times: ms per frame, iterations,
# stalled steps, the least distance between bodies over the run, and the
# share of step time contact took on rank 0 by part (pair search, ghosts,
# terms, guard; `descent run`'s report).
#
#   bench/contact_bodies.sh [BUILD_DIR]
#   RUNS=3 FRAMES=30 bench/contact_bodies.sh
#   SCENES="pile snowman" bench/contact_bodies.sh     # a subset
#   SCENES=pile RANKS="1 2 3 4" bench/contact_bodies.sh  # other rank counts
#   BASELINE=/path/to/other/build bench/contact_bodies.sh
#     # each run also with that build's descent (built by the caller),
#     # interleaved, so before/after ratios come from one run
#
# Writes bench/results/contact/contact_bodies.csv (one line per run) and
# contact_bodies.log (the machine, the commands, the medians).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build}
runs=${RUNS:-3}
frames=${FRAMES:-30}
scratch=${SCRATCH:-/tmp/descent_contact_bodies}
python=${PYTHON:-/usr/bin/python3}
out=$root/bench/results/contact
mkdir -p "$out" "$scratch"
log=$out/contact_bodies.log
# A subset writes its own table beside the full one.
subset=${SCENES:+_${SCENES// /_}}${RANKS:+_ranks${RANKS// /}}
csv=$out/contact_bodies$subset.csv
echo "build,scene,ranks,run,frames,ms_per_frame,iterations,stalled,least_distance,contact_share,search_ms,ghosts_ms,terms_ms,guard_ms,paths_caught" >"$csv"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMP_NUM_THREADS=1

cmake --build "$build" --target descent -j2 >/dev/null
bin=$build/src/app/descent
builds=(current)
if [[ -n ${BASELINE:-} ]]; then
  [[ -x $BASELINE/src/app/descent ]] || { echo "contact_bodies: no $BASELINE/src/app/descent" >&2; exit 1; }
  builds+=(baseline)
fi
{
  echo "== $(date -u +%FT%TZ) contact between bodies"
  echo "machine: $(lscpu | sed -n 's/^Model name: *//p'), $(nproc --all) cores; no GPU used"
  echo "tree: $(git -C "$root" rev-parse --short HEAD) (+ working tree)"
  echo "runs $runs, frames $frames, OMP_NUM_THREADS=1; load before: $(cut -d' ' -f1-3 /proc/loadavg)"
  if [[ -n ${BASELINE:-} ]]; then
    echo "baseline: a build of $(git -C "$BASELINE/.." rev-parse --short HEAD 2>/dev/null || echo '?') (BASELINE=<its build directory>)"
  fi
  echo "command: mpiexec -n RANKS ${bin#"$root"/} run jobs/contact/SCENE.toml --set time.frames=$frames"
} | tee -a "$log"

for scene in ${SCENES:-bodies_floor snowman bowling pile}; do
  for ranks in ${RANKS:-1 2}; do
    for k in $(seq 1 "$runs"); do
      for which in "${builds[@]}"; do
        dir=$scratch/$scene.$ranks.$k.$which
        rm -rf "$dir"
        exe=$bin
        [[ $which == baseline ]] && exe=$BASELINE/src/app/descent
        mpiexec --oversubscribe -n "$ranks" "$exe" run "$root/jobs/contact/$scene.toml" \
          --set "output.dir=\"$dir\"" --set "time.frames=$frames" >"$dir.out" 2>&1
        "$python" - "$dir/stats.csv" "$dir.out" "$which" "$scene" "$ranks" "$k" "$frames" >>"$csv" <<'PY'
import csv, re, statistics, sys
rows = list(csv.DictReader(open(sys.argv[1])))
ms = statistics.mean(float(r["wall_ms"]) for r in rows)
its = sum(int(r["iterations"]) for r in rows)
stalled = sum(int(r["stalled"]) for r in rows)
least = min(float(r["body_contact_least_distance"]) for r in rows)
text = open(sys.argv[2]).read()
m = re.search(r"contact between bodies ([0-9.]+)% .*pair search ([0-9.]+) ms, ghosts ([0-9.]+) ms, "
              r"terms ([0-9.]+) ms, guard ([0-9.]+) ms; ([0-9]+) path", text)
parts = list(m.groups()) if m else ["", "", "", "", "", ""]
print(",".join(sys.argv[3:8] + [f"{ms:.1f}", str(its), str(stalled), f"{least:.3g}"] + parts))
PY
      done
    done
  done
done

"$python" - "$csv" <<'PY' | tee -a "$log"
import csv, statistics, sys
rows = list(csv.DictReader(open(sys.argv[1])))
print("build     scene          ranks  ms/frame (median)  iterations  stalled  least distance  contact share (median)  paths caught")
for key in sorted({(r["scene"], r["ranks"], r["build"]) for r in rows}):
    mine = [r for r in rows if (r["scene"], r["ranks"], r["build"]) == key]
    med = lambda f: statistics.median(float(r[f]) for r in mine)
    share = statistics.median(float(r["contact_share"] or "nan") for r in mine)
    print(f"{key[2]:9s} {key[0]:14s} {key[1]:>5s}  {med('ms_per_frame'):17.1f}  {mine[0]['iterations']:>10s}  "
          f"{mine[0]['stalled']:>7s}  {float(mine[0]['least_distance']):14.3g}  {share:21.1f}%  {mine[0]['paths_caught']:>12s}")
PY
