#!/usr/bin/env bash
# Issue 25's figures: the multilevel preconditioner inside the descent
# against Jacobi's and PETSc's GAMG, and the methods around it. Results in
# $ML_RESULTS (bench/results/multilevel by default), each with its
# machine.txt; tables and plots by tools/multilevel_figures.py.
#   jobs/study/multilevel.sh [resolution] [poisson] [stiff] [mainjob] [refresh]
#                            [bound] [stopping]
#  resolution: iterations and rank 0's time to e <= 1e-1 .. 1e-5 on the
#              helix at 41K, 82K, 158K, 316K and 1M tets (resolution 7.15),
#              2 ranks, 1 measured frame after 5 of 96 Jacobi iterations:
#              Chebyshev with jacobi, multilevel and petsc_gamg; NCG and
#              L-BFGS with jacobi and multilevel; Newton with PETSc's GAMG
#  poisson:    the 158K helix at Poisson 0.3, 0.45, 0.49, 0.499, Chebyshev
#              with both preconditioners
#  stiff:      the armadillo of ../shared/meshes at E = 1e5 and 1e7 (skipped
#              without it): multilevel Chebyshev against L-BFGS
#  mainjob:    `descent run` of the main job (82K, 1e-2 a step, 2 ranks, 60
#              frames), jacobi and multilevel, 3 runs each: ms per frame,
#              set-up, peak memory, the preconditioner's costs
#  refresh:    the main job with solver.preconditioner_refresh = 1, 2, 4:
#              ms per frame and iterations per step
#  bound:      the 316K helix, where multilevel Chebyshev fell below its
#              bound: Lanczos at the refresh state with 20, 100 and 300
#              steps, and b widened by spectrum_margin 0.3 and 0.6
#  stopping:   multilevel Chebyshev at every size with solver.accuracy
#              1e-2 .. 1e-6: where the step stops and the error there
#              (into stopping/$STOPPING_LABEL, default "current": with
#              DESCENT=<an older binary> and another label, a comparison)
# SIZES="41k 1M" limits the resolution and stopping parts to those sizes. Needs a build
# with PETSc (Newton's truth eps* is solved with its GAMG, as are two cases).
source "$(dirname "$0")/common.sh"
parts=("$@")
[ ${#parts[@]} -gt 0 ] || parts=(resolution poisson stiff mainjob refresh)
base=${ML_RESULTS:-bench/results/multilevel}
mkdir -p "$base"
TRUTH=(--truth-solver petsc)
ML='preconditioner="multilevel"'
GAMG='preconditioner="petsc_gamg"'

# The helix scene at a named size, with the paper's 96 iterations a step for
# the warm-up: the main job's file with its preset replaced (preset and
# resolution exclude each other in one file).
helix_scene() {  # helix_scene SIZE -> path of a scene file
  local size=$1 file="$base/scenes/helix_$1.toml"
  mkdir -p "$base/scenes"
  if [ "$size" = 1M ]; then
    sed 's/^preset = .*/resolution = 7.15    # about 1M tets/' jobs/helix.toml > "$file"
  else
    sed "s/^preset = .*/preset = \"$size\"/" jobs/helix.toml > "$file"
  fi
  echo "$file"
}

study() {  # study OUT SCENE [descent study arguments]: one study, with its machine
  local out=$1 scene=$2
  shift 2
  mkdir -p "$out"
  # The warm-up as the issue measured it: 96 Jacobi-preconditioned
  # iterations a frame (cases name their own preconditioner).
  local cmd=($MPIEXEC -n 2 "$DESCENT" study "$scene" --set solver.accuracy=0
             --set solver.iterations=96 "${JACOBI[@]}" "${TRUTH[@]}" --warmup 5 --frames 1 "$@"
             --study-out "$out")
  machine "${cmd[*]}" > "$out/machine.txt"
  "${cmd[@]}" > "$out/progress.log" 2>&1
  gzip -f "$out/study.csv"
}

resolution() {
  # size | Jacobi iterations (Chebyshev, NCG, L-BFGS) past 1e-5 (measured
  # at 41K: 358, 239, 276; grown as N^(1/3) with room) | repeats
  local entries=("41k|450 320 360|3" "82k|500 400 450|3" "158k|600 500 550|3"
                 "316k|760 650 750|3" "1M|1150 950 1100|1")
  for entry in "${entries[@]}"; do
    IFS='|' read -r size caps repeats <<<"$entry"
    if [ -n "${SIZES:-}" ] && [[ " $SIZES " != *" $size "* ]]; then continue; fi
    read -r n_cheb n_ncg n_lbfgs <<<"$caps"
    cases=(--case "chebyshev_jacobi:method=chebyshev iterations=$n_cheb"
           --case "chebyshev_multilevel:method=chebyshev $ML iterations=80"
           --case "chebyshev_petsc_gamg:method=chebyshev $GAMG iterations=80"
           --case "ncg_jacobi:method=ncg iterations=$n_ncg"
           --case "ncg_multilevel:method=ncg $ML iterations=80"
           --case "lbfgs_jacobi:method=lbfgs iterations=$n_lbfgs"
           --case "lbfgs_multilevel:method=lbfgs $ML iterations=80"
           --case "newton_petsc_gamg:method=newton newton_solver=\"petsc\"")
    study "$base/resolution/helix_$size" "$(helix_scene "$size")" --repeats "$repeats" "${cases[@]}"
  done
}

poisson() {
  for nu in 0.3 0.45 0.49 0.499; do
    study "$base/poisson/nu_$nu" "$(helix_scene 158k)" --set material.poisson=$nu --repeats 1 \
      --case "chebyshev_jacobi:method=chebyshev iterations=3000" \
      --case "chebyshev_multilevel:method=chebyshev $ML iterations=400"
  done
}

stiff() {
  local armadillo=../shared/meshes/armadillo_10k.node
  if [ ! -f "$armadillo" ]; then
    echo "multilevel.sh: $armadillo not found: the armadillo part is skipped" >&2
    return
  fi
  for young in 1e5 1e7; do
    study "$base/stiff/armadillo_E$young" jobs/study/armadillo.toml --set material.young=$young \
      --repeats 3 \
      --case "chebyshev_jacobi:method=chebyshev iterations=3000" \
      --case "chebyshev_multilevel:method=chebyshev $ML iterations=200" \
      --case "lbfgs_jacobi:method=lbfgs iterations=2000" \
      --case "lbfgs_multilevel:method=lbfgs $ML iterations=200" \
      --case "ncg_multilevel:method=ncg $ML iterations=200"
  done
}

run_main_job() {  # run_main_job OUT [descent run arguments]
  local out=$1
  shift
  local cmd=($MPIEXEC -n 2 "$DESCENT" run jobs/helix.toml --overwrite --out "$out" "$@")
  machine "${cmd[*]}" > "$out.machine.txt"
  "${cmd[@]}" > "$out.log" 2>&1
}

mainjob() {
  mkdir -p "$base/mainjob"
  for run in 1 2 3; do
    for p in jacobi multilevel; do
      run_main_job "$base/mainjob/${p}_$run" --set "solver.preconditioner=\"$p\""
    done
  done
  # Frames are not kept (60 frames of 82K tets); the logs and stats are.
  rm -f "$base"/mainjob/*_[123]/frames.*
}

refresh() {
  mkdir -p "$base/refresh"
  for every in 1 2 4; do
    run_main_job "$base/refresh/every_$every" --set "solver.$ML" \
      --set solver.preconditioner_refresh=$every
  done
  rm -f "$base"/refresh/every_*/frames.*
}

bound() {
  study "$base/bound/helix_316k" "$(helix_scene 316k)" --repeats 1 \
    --case "lanczos_20:method=chebyshev $ML iterations=60" \
    --case "lanczos_100:method=chebyshev $ML iterations=60 spectrum_steps=100" \
    --case "lanczos_300:method=chebyshev $ML iterations=60 spectrum_steps=300" \
    --case "margin_0.3:method=chebyshev $ML iterations=60 spectrum_margin=0.3" \
    --case "margin_0.6:method=chebyshev $ML iterations=60 spectrum_margin=0.6"
}

stopping() {
  local label=${STOPPING_LABEL:-current} size cases target
  for size in 41k 82k 158k 316k 1M; do
    if [ -n "${SIZES:-}" ] && [[ " $SIZES " != *" $size "* ]]; then continue; fi
    cases=()
    for target in 1e-2 1e-3 1e-4 1e-5 1e-6; do
      cases+=(--case "accuracy_$target:method=chebyshev $ML accuracy=$target iterations=200")
    done
    study "$base/stopping/$label/helix_$size" "$(helix_scene "$size")" --repeats 1 "${cases[@]}"
  done
}

for part in "${parts[@]}"; do "$part"; done
$PYTHON tools/multilevel_figures.py "$base"
