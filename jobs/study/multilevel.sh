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
#  unseen:     every mesh of ../shared/meshes (skipped without them; the
#              .vtu converted by meshio), scaled to 1 m and held at its
#              lowest 5%, under four materials (neo-Hookean soft and nearly
#              incompressible-stiff, StVK, corotated): the automatic
#              preconditioner against Jacobi's to 1e-2, and to 1e-4, with
#              the error where each step stops; and `descent run` of the
#              soft raptor (it collapses) for 30 frames with each
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

# A scene for a mesh file: scaled to 1 m tall, its lowest 5% held.
mesh_scene() {  # mesh_scene MESH MODEL YOUNG POISSON OUT
  local mesh=$1 model=$2 young=$3 poisson=$4 out=$5
  $PYTHON - "$mesh" "$model" "$young" "$poisson" "$out" > "$out" <<'PY'
import os, sys, meshio
mesh, model, young, poisson, out = sys.argv[1:]
p = meshio.read(mesh).points
mesh = os.path.relpath(mesh, os.path.dirname(os.path.abspath(out)))  # as scenes name files
scale = 1.0 / (p[:, 1].max() - p[:, 1].min())
held = (p[:, 1].min() + 0.05 * (p[:, 1].max() - p[:, 1].min())) * scale
print(f'''gravity = [0.0, -9.81, 0.0]
[mesh]
file = "{mesh}"
scale = {scale:.6g}
[material]
model = "{model}"
young = {young}
poisson = {poisson}
density = 1000
[[fixed]]
box_min = [-1e3, -1e3, -1e3]
box_max = [1e3, {held:.6g}, 1e3]
axes = "xyz"
[time]
dt = 0.03333333333333333
[solver]
method = "chebyshev"''')
PY
}

unseen() {
  local shared=../shared/meshes tmp mesh name material model young poisson
  if [ ! -d "$shared" ]; then
    echo "multilevel.sh unseen: $shared is absent: skipped" >&2
    return
  fi
  tmp=$(mktemp -d)
  mkdir -p "$base/unseen/scenes"
  for mesh in "$shared"/*.ele "$shared"/*.msh "$shared"/*.mesh "$shared"/*.vtu; do
    [ -e "$mesh" ] || continue
    name=$(basename "${mesh%.*}")
    if [[ $mesh == *.vtu ]]; then  # not a format descent reads: Gmsh 2.2 by meshio
      $PYTHON -c "import meshio, sys; meshio.write(sys.argv[2], meshio.read(sys.argv[1]), file_format='gmsh22', binary=False)" \
        "$mesh" "$tmp/$name.msh"
      mesh=$tmp/$name.msh
    fi
    [[ $mesh == *.ele ]] && mesh=${mesh%.ele}.node
    for material in "neo_hookean 1e5 0.3" "neo_hookean 1e7 0.49" "stvk 1e6 0.4" "corotated 1e6 0.45"; do
      read -r model young poisson <<<"$material"
      local scene="$base/unseen/scenes/${name}_${model}_${young}_${poisson}.toml"
      mesh_scene "$mesh" "$model" "$young" "$poisson" "$scene"
      [[ $mesh == "$tmp"/* ]] &&
        sed -i "1i # [mesh] file: $(basename "$mesh") converted by meshio from ../shared/meshes at run time (jobs/study/multilevel.sh unseen)" "$scene"
      study "$base/unseen/${name}_${model}_${young}_${poisson}" "$scene" --repeats 1 \
        --case "auto_1e-2:method=chebyshev preconditioner=\"auto\" accuracy=1e-2 iterations=1000" \
        --case "jacobi_1e-2:method=chebyshev accuracy=1e-2 iterations=4000" \
        --case "auto_1e-4:method=chebyshev preconditioner=\"auto\" accuracy=1e-4 iterations=1000"
    done
  done
  # The soft raptor, as a user would run it: 30 frames to 1e-2 a step.
  local raptor="$base/unseen/scenes/raptorTetra_19409_neo_hookean_1e5_0.3.toml"
  if [ -e "$tmp/raptorTetra_19409.msh" ]; then
    sed "s#^file = .*#file = \"$tmp/raptorTetra_19409.msh\"#" "$raptor" > "$tmp/raptor.toml"
    mkdir -p "$base/unseen/raptor_runs"
    for pre in auto jacobi; do
      local out="$base/unseen/raptor_runs/$pre"
      local cmd=($MPIEXEC -n 2 "$DESCENT" run "$tmp/raptor.toml" --overwrite --out "$out"
                 --set time.frames=30 --set solver.accuracy=1e-2 --set solver.iterations=1000
                 --set "solver.preconditioner=\"$pre\"")
      machine "${cmd[*]}" > "$out.machine.txt"
      "${cmd[@]}" > "$out.log" 2>&1
      rm -f "$out"/frames.* "$out"/checkpoint/*
    done
  fi
  rm -rf "$tmp"
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
