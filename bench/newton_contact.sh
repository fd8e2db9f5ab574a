#!/usr/bin/env bash
# Newton on a landing (docs/contact.md, "Newton"): the 41K helix let go onto
# the floor (jobs/contact/helix_floor.toml), 7 frames at solver.accuracy =
# 1e-8, its CG preconditioned by Jacobi's diagonal or by the multilevel
# V-cycle (rebuilt at each Newton iterate, the floor's contact blocks in).
# RUNS runs of each, the two taken in turn; per run and frame the wall ms,
# Newton iterations, line-search halvings, eps and the floor's force from
# stats.csv.
#
#   RUNS=3 bench/newton_contact.sh [BUILD_DIR]     # default build
#
# Writes bench/results/newton_contact/newton_contact.csv (replaced) and a log
# beside it with the machine and the commands.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build}
runs=${RUNS:-3}
out=$root/bench/results/newton_contact
mkdir -p "$out"
csv=$out/newton_contact.csv
log=$out/newton_contact.log
cmake --build "$build" --target descent -j2 >/dev/null
export OMP_NUM_THREADS=1 OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
{
  echo "# $(date -u '+%Y-%m-%d %H:%M UTC'), $(git -C "$root" rev-parse --short HEAD)"
  echo "# $(lscpu | sed -n 's/^Model name: *//p'), $(getconf _NPROCESSORS_ONLN) logical cores, one rank, OMP_NUM_THREADS=1"
} >"$log"
echo "preconditioner,run,frame,iterations,halvings,energy,wall_ms,floor_force_y,contacts" >"$csv"
for run in $(seq 1 "$runs"); do
  for pc in multilevel jacobi; do
    cmd=("$build/src/app/descent" run "$root/jobs/contact/helix_floor.toml" --overwrite
         --out "$scratch/$pc" --set "mesh.helix.preset='41k'" --set "solver.method='newton'"
         --set solver.accuracy=1e-8 --set time.frames=7 --set "solver.preconditioner='$pc'")
    echo "$(date -u +%T) run $run: ${cmd[*]}" >>"$log"
    "${cmd[@]}" >>"$log" 2>&1
    # stats.csv columns by name: frame, iterations, rollbacks, energy, wall_ms,
    # obstacle0_force_y, obstacle0_contacts.
    awk -F, -v pc="$pc" -v run="$run" '
      NR == 1 { for (i = 1; i <= NF; ++i) col[$i] = i; next }
      { print pc "," run "," $col["frame"] "," $col["iterations"] "," $col["rollbacks"] "," \
              $col["energy"] "," $col["wall_ms"] "," $col["obstacle0_force_y"] "," \
              $col["obstacle0_contacts"] }' "$scratch/$pc/stats.csv" >>"$csv"
  done
done
