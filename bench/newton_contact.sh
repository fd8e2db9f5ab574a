#!/usr/bin/env bash
# Newton on contact scenes (docs/contact.md, "Newton"), its CG
# preconditioned by Jacobi's diagonal or by the multilevel V-cycle (rebuilt
# at each Newton iterate with the obstacles' contact blocks and the pairs'
# diagonal in its finest operator), solver.accuracy = 1e-6 unless a case
# says otherwise. RUNS runs of each, the two taken in turn; per run and
# frame the wall ms, Newton iterations, line-search halvings, eps and the
# error estimate from stats.csv.
#
#   RUNS=3 bench/newton_contact.sh [BUILD_DIR]                  # default build
#   CASES="snowman:20 pile:20" NAME=newton_contact_bodies RUNS=1 bench/newton_contact.sh
#
# A case is SCENE:FRAMES[:HELIX_PRESET[:ACCURACY]] of jobs/contact/SCENE.toml;
# the default is the 41K helix let go onto the floor, 7 frames at 1e-8.
# Writes bench/results/newton_contact/NAME.csv (replaced; NAME defaults to
# newton_contact) and NAME.log beside it with the machine and the commands.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build}
runs=${RUNS:-3}
cases=${CASES:-"helix_floor:7:41k:1e-8"}
name=${NAME:-newton_contact}
out=$root/bench/results/newton_contact
mkdir -p "$out"
csv=$out/$name.csv
log=$out/$name.log
cmake --build "$build" --target descent -j2 >/dev/null
export OMP_NUM_THREADS=1 OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
{
  echo "# $(date -u '+%Y-%m-%d %H:%M UTC'), $(git -C "$root" rev-parse --short HEAD)"
  echo "# $(lscpu | sed -n 's/^Model name: *//p'), $(getconf _NPROCESSORS_ONLN) logical cores, one rank, OMP_NUM_THREADS=1"
} >"$log"
echo "case,preconditioner,run,frame,iterations,halvings,energy,wall_ms,error_estimate" >"$csv"
for c in $cases; do
  IFS=: read -r scene frames preset accuracy <<<"$c"
  keys=(--set "solver.method='newton'" --set "solver.accuracy=${accuracy:-1e-6}"
        --set "time.frames=$frames")
  [[ -n $preset ]] && keys+=(--set "mesh.helix.preset='$preset'")
  for run in $(seq 1 "$runs"); do
    for pc in multilevel jacobi; do
      cmd=("$build/src/app/descent" run "$root/jobs/contact/$scene.toml" --overwrite
           --out "$scratch/$pc" "${keys[@]}" --set "solver.preconditioner='$pc'")
      # Paths in the log relative to the repository, the scratch folder as SCRATCH.
      echo "$(date -u +%T) run $run: ${cmd[*]}" | sed -e "s|$root/||g" -e "s|$scratch|SCRATCH|g" >>"$log"
      "${cmd[@]}" >>"$log" 2>&1
      awk -F, -v c="$c" -v pc="$pc" -v run="$run" '
        NR == 1 { for (i = 1; i <= NF; ++i) col[$i] = i; next }
        { print c "," pc "," run "," $col["frame"] "," $col["iterations"] "," $col["rollbacks"] \
                "," $col["energy"] "," $col["wall_ms"] "," $col["error_estimate"] }' \
        "$scratch/$pc/stats.csv" >>"$csv"
    done
  done
done
