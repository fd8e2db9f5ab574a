#!/usr/bin/env bash
# The two formulations of contact side by side (docs/contact.md, issue 21):
# contact.method = "energy" (a barrier in eps, no iterate crossing) and
# "projection" (the step solved without contact, its result pushed apart),
# on jobs/contact/{head_on,bowling,snowman,pile}.toml, 1 and 2 ranks, each
# RUNS times: the frames a run completes (a run stops at a step with no
# finite state), ms per frame, iterations, the deepest penetration the
# solves produced (bodies and obstacles; "energy" has none by
# construction), the least distance between bodies after the steps, and
# the largest drift of the total momentum relative to the initial one
# (meaningful without gravity and obstacles: head_on).
#
#   bench/contact_methods.sh [BUILD_DIR]
#   RUNS=3 FRAMES=30 SCENES="head_on bowling" RANKS="1 2" bench/contact_methods.sh
#
# Writes bench/results/contact/contact_methods.csv (one line per run) and
# contact_methods.log (the machine, the commands, the medians).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build}
runs=${RUNS:-3}
frames=${FRAMES:-30}
scratch=${SCRATCH:-/tmp/descent_contact_methods}
python=${PYTHON:-/usr/bin/python3}
out=$root/bench/results/contact
mkdir -p "$out" "$scratch"
log=$out/contact_methods.log
csv=$out/contact_methods.csv
echo "scene,method,ranks,run,frames,completed,ms_per_frame,iterations,body_penetration,obstacle_penetration,least_distance,momentum_drift,stopped" >"$csv"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMP_NUM_THREADS=1

cmake --build "$build" --target descent -j2 >/dev/null
bin=$build/src/app/descent
{
  echo "== $(date -u +%FT%TZ) contact methods side by side"
  echo "machine: $(lscpu | sed -n 's/^Model name: *//p'), $(nproc --all) cores; no GPU used"
  echo "tree: $(git -C "$root" rev-parse --short HEAD) (+ working tree)"
  echo "runs $runs, frames $frames, OMP_NUM_THREADS=1; load before: $(cut -d' ' -f1-3 /proc/loadavg)"
  echo "command: mpiexec -n RANKS ${bin#"$root"/} run jobs/contact/SCENE.toml --set time.frames=$frames --set contact.method=\\\"METHOD\\\""
} | tee -a "$log"

for scene in ${SCENES:-head_on bowling snowman pile}; do
  for method in energy projection; do
    for ranks in ${RANKS:-1 2}; do
      for k in $(seq 1 "$runs"); do
        dir=$scratch/$scene.$method.$ranks.$k
        rm -rf "$dir"
        mpiexec --oversubscribe -n "$ranks" "$bin" run "$root/jobs/contact/$scene.toml" \
          --set "output.dir=\"$dir\"" --set "time.frames=$frames" \
          --set "contact.method=\"$method\"" >"$dir.out" 2>&1 || true
        "$python" - "$dir/stats.csv" "$dir.out" "$scene" "$method" "$ranks" "$k" "$frames" >>"$csv" <<'PY'
import csv, math, re, statistics, sys
rows = [r for r in csv.DictReader(open(sys.argv[1]))
        if all(math.isfinite(float(v)) for k, v in r.items() if k in ("wall_ms", "energy"))]
ms = statistics.mean(float(r["wall_ms"]) for r in rows) if rows else float("nan")
its = sum(int(r["iterations"]) for r in rows)
def most(name):
    vals = [float(r[name]) for r in rows if name in r]
    return max(vals) if vals else 0.0
least = min((float(r["body_contact_least_distance"]) for r in rows), default=float("nan"))
bodies = sorted({int(k[4:k.index("_")]) for k in (rows[0] if rows else {}) if k.startswith("body") and k.endswith("_momentum_x")})
def momentum(r):
    return [sum(float(r[f"body{b}_momentum_{a}"]) for b in bodies) for a in "xyz"]
drift = float("nan")
if rows:
    scale = sum(math.sqrt(sum(float(rows[0][f"body{b}_momentum_{a}"]) ** 2 for a in "xyz")) for b in bodies)
    p0 = momentum(rows[0])
    drift = max(math.dist(momentum(r), p0) for r in rows) / scale if scale > 0 else float("nan")
text = open(sys.argv[2]).read()
m = re.search(r"error: (.*)", text)
stopped = m.group(1).split(";")[0].replace(",", " ")[:90] if m else ""
print(",".join(sys.argv[3:8] + [str(len(rows)), f"{ms:.1f}", str(its), f"{most('body_contact_penetration'):.3g}",
                                 f"{most('contact_penetration'):.3g}", f"{least:.3g}", f"{drift:.2g}", stopped]))
PY
      done
    done
  done
done

"$python" - "$csv" <<'PY' | tee -a "$log"
import csv, statistics, sys
rows = list(csv.DictReader(open(sys.argv[1])))
print("scene      method      ranks  completed  ms/frame (median)  iterations  body pen.  obstacle pen.  least dist.  momentum drift  stopped")
for key in sorted({(r["scene"], r["method"], r["ranks"]) for r in rows}, key=lambda k: (k[0], k[1], int(k[2]))):
    mine = [r for r in rows if (r["scene"], r["method"], r["ranks"]) == key]
    ms = statistics.median(float(r["ms_per_frame"]) for r in mine)
    r = mine[0]
    print(f"{key[0]:10s} {key[1]:11s} {key[2]:>5s}  {r['completed']:>4s}/{r['frames']:<4s}  {ms:17.1f}  {r['iterations']:>10s}  "
          f"{r['body_penetration']:>9s}  {r['obstacle_penetration']:>13s}  {r['least_distance']:>11s}  {r['momentum_drift']:>14s}  {r['stopped']}")
PY
