#!/usr/bin/env bash
# The contact barrier in the methods that evaluate it (docs/contact.md,
# Methods): chebyshev, lbfgs, jacobi_gd and nesterov side by side on paper 2's
# scenes at its dt = 1/150, each step solved to e <= 1e-6 (cap 20,000
# iterations), measured by `descent study` (truth: the lower eps of newton's
# and of chebyshev run to round-off). Per scene and method: the steps that met the target, the
# median iterations and the median ms per step to the target.
#
#   bench/contact_barrier_methods.sh [BUILD_DIR]
#   SCENES="snowman" METHODS="chebyshev nesterov" bench/contact_barrier_methods.sh
#
# Writes bench/results/contact/contact_barrier_methods.log (machine,
# commands, table); the studies' csv stay in $SCRATCH.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build}
scratch=${SCRATCH:-/tmp/descent_barrier_methods}
python=${PYTHON:-/usr/bin/python3}
out=$root/bench/results/contact
mkdir -p "$out" "$scratch"
log=$out/contact_barrier_methods.log
export OMP_NUM_THREADS=1
cmake --build "$build" --target descent -j2 >/dev/null
bin=$build/src/app/descent
{
  echo "== $(date -u +%FT%TZ) the contact barrier per method"
  echo "machine: $(lscpu | sed -n 's/^Model name: *//p'), $(nproc --all) cores, 1 rank, no GPU"
  echo "tree: $(git -C "$root" rev-parse --short HEAD) (+ working tree); load before: $(cut -d' ' -f1-3 /proc/loadavg)"
} | tee -a "$log"
# Measured steps per scene (warmup, frames, every): bowling's ball meets the
# head pin near step 21, the snowman settles from its start, the spinning
# cars meet near step 93.
declare -A schedule=([bowling]="12 6 6" [snowman]="4 6 6" [cars_spin]="86 3 6")
for scene in ${SCENES:-bowling snowman cars_spin}; do
  read -r warmup frames every <<<"${schedule[$scene]}"
  dir=$scratch/$scene
  cmd=("$bin" study "$root/jobs/contact/$scene.toml" --set "time.dt=0.006666666666666667"
       --warmup "$warmup" --frames "$frames" --every "$every" --repeats 1 --study-out "$dir" --quiet)
  methods=${METHODS:-chebyshev lbfgs jacobi_gd nesterov}
  for method in $methods; do
    cmd+=(--case "$method:method=$method accuracy=1e-6 iterations=20000")
  done
  echo "command: ${cmd[*]#"$root"/}" | tee -a "$log"
  "${cmd[@]}"
  "$python" - "$dir" "$scene" $methods <<'PY' | tee -a "$log"
import csv, statistics, sys
d, scene, methods = sys.argv[1], sys.argv[2], sys.argv[3:]
rows = list(csv.DictReader(open(f"{d}/study.csv")))
acc = {r["case"]: r for r in csv.DictReader(open(f"{d}/accuracy.csv"))}
print(f"{scene}: method, steps meeting 1e-6 / measured, median iterations, median ms per step, per step (iterations, e)")
for case in methods:
    last = {}
    for r in rows:
        if r["case"] == case:
            last[r["frame"]] = r
    its = [int(r["k"]) for r in last.values()]
    ms = [float(r["ms"]) for r in last.values()]
    steps = ", ".join(f"{int(r['k'])} ({float(r['rel_error']):.1e})" for f, r in sorted(last.items(), key=lambda x: int(x[0])))
    print(f"  {case:10s} {acc[case]['met']}/{acc[case]['steps']}  {statistics.median(its):8.0f}  {statistics.median(ms):10.1f}  {steps}")
PY
done
