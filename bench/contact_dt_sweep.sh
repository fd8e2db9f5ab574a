#!/usr/bin/env bash
# The largest time step contact between bodies survives (issue 21): two
# boxes thrown at each other (jobs/contact/head_on.toml), the thrown ball
# (bowling.toml) and the pile (pile.toml) over the
# same SPAN seconds at each dt in DTS, on RANKS ranks: whether the run
# completes, non-finite rollbacks, stalled steps, the least distance between
# bodies over every frame (positive: no crossing at any frame; every iterate
# between is proven by the guard, docs/contact.md), paths the guard could not
# prove, ms per frame; for each contact.method in METHODS ("energy", the
# barrier, and "projection", the pass after the solve). The projection's
# penetration column is the deepest the solves went before the passes.
#
#   bench/contact_dt_sweep.sh [BUILD_DIR]
#   DTS="1/120 1/60 1/30 1/15" SPAN=0.5 RANKS=2 METHODS=energy bench/contact_dt_sweep.sh
#
# Writes bench/results/contact/contact_dt_sweep.csv and appends the machine,
# the commands and the table to contact_dt_sweep.log.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build}
dts=${DTS:-1/300 1/150 1/60 1/30 1/15 1/8}
span=${SPAN:-0.5}
ranks=${RANKS:-2}
methods=${METHODS:-energy projection}
scratch=${SCRATCH:-/tmp/descent_contact_dt}
python=${PYTHON:-/usr/bin/python3}
out=$root/bench/results/contact
mkdir -p "$out" "$scratch"
log=$out/contact_dt_sweep.log
csv=$out/contact_dt_sweep.csv
echo "scene,method,dt,frames,completed,nonfinite_rollbacks,stalled,least_distance,penetration,paths_caught,ms_per_frame" >"$csv"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMP_NUM_THREADS=1

cmake --build "$build" --target descent -j2 >/dev/null
bin=$build/src/app/descent
{
  echo "== $(date -u +%FT%TZ) largest dt with contact between bodies"
  echo "machine: $(lscpu | sed -n 's/^Model name: *//p'), $(nproc --all) cores; no GPU used; load $(cut -d' ' -f1-3 /proc/loadavg)"
  echo "tree: $(git -C "$root" rev-parse --short HEAD) (+ working tree)"
  echo "span $span s, ranks $ranks, OMP_NUM_THREADS=1"
  echo "command: mpiexec -n $ranks ${bin#"$root"/} run jobs/contact/SCENE.toml --set time.dt=DT --set time.frames=SPAN/DT --set contact.method=\\\"METHOD\\\""
} | tee -a "$log"

for scene in ${SCENES:-head_on bowling pile}; do
  for method in $methods; do
    for dt in $dts; do
      frames=$("$python" -c "import math; print(max(1, math.ceil($span / ($dt) - 1e-9)))")
      value=$("$python" -c "print(repr(float($dt)))")
      dir=$scratch/$scene.$method.${dt/\//_}
      rm -rf "$dir"
      completed=1
      mpiexec --oversubscribe -n "$ranks" "$bin" run "$root/jobs/contact/$scene.toml" \
        --set "output.dir=\"$dir\"" --set "time.dt=$value" --set "time.frames=$frames" \
        --set "contact.method=\"$method\"" >"$dir.out" 2>&1 || completed=0
      "$python" - "$dir/stats.csv" "$dir.out" "$scene" "$method" "$dt" "$frames" "$completed" >>"$csv" <<'PY'
import csv, math, os, re, statistics, sys
path, out, scene, method, dt, frames, completed = sys.argv[1:8]
rows = list(csv.DictReader(open(path))) if os.path.exists(path) else []
rows = [r for r in rows if math.isfinite(float(r["energy"]))]
text = open(out).read()
caught = re.search(r"; ([0-9]+) path\(s\) not proven", text)
deepest = max((float(r.get(k) or 0) for r in rows for k in ("body_contact_penetration", "contact_penetration")), default=0.0)
fields = [scene, method, dt, frames, completed,
          str(sum(int(r["nonfinite_rollbacks"]) for r in rows)),
          str(sum(int(r["stalled"]) for r in rows)),
          f"{min(float(r['body_contact_least_distance']) for r in rows):.3g}" if rows else "",
          f"{deepest:.3g}",
          caught.group(1) if caught else "",
          f"{statistics.mean(float(r['wall_ms']) for r in rows):.1f}" if rows else ""]
print(",".join(fields))
PY
    done
  done
done

"$python" - "$csv" <<'PY' | tee -a "$log"
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
print("scene    method      dt      frames  completed  nonfinite  stalled  least distance  penetration  paths caught  ms/frame")
for r in rows:
    print(f"{r['scene']:8s} {r['method']:11s} {r['dt']:7s} {r['frames']:>6s}  {r['completed']:>9s}  {r['nonfinite_rollbacks']:>9s}  "
          f"{r['stalled']:>7s}  {r['least_distance']:>14s}  {r['penetration']:>11s}  {r['paths_caught']:>12s}  {r['ms_per_frame']:>8s}")
PY
