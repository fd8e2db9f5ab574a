#!/usr/bin/env bash
# Figures that Jacobi-CG Newton made unaffordable, with the AMG Newton
# (solver.newton_solver = "petsc", docs/petsc.md) as the truth eps*:
#   fig6   paper 1's Fig. 6, the four initialisations over 100 frames of the
#          82K helix (Newton every frame), 2 ranks;
#   fig2c  paper 1's Fig. 2c, the methods at the paper's 96 iterations, on
#          the 158K and 316K helix, 2 ranks;
#   pareto the 82K helix's Pareto front (jobs/study/automatic.sh's cases)
#          with the AMG Newton's own iterations added, 2 ranks.
#   jobs/study/amg_truth.sh [fig6|fig2c|pareto]...   (default: all three)
# Needs a build with PETSc (Debian petsc-dev).
source "$(dirname "$0")/common.sh"
base="$RESULTS/amg_truth"
AMG=(--truth-solver petsc)
helix_of() {  # helix_of PRESET: the 96-iteration helix args at that size
  echo jobs/helix.toml --set "mesh.helix.preset=\"$1\"" --set solver.accuracy=0 \
    --set solver.iterations=96
}
study() {  # study OUT ARGS...: one descent study with its machine record
  local out=$1
  shift
  mkdir -p "$out"
  local cmd=($MPIEXEC -n 2 "$DESCENT" study "$@" "${JACOBI[@]}" "${AMG[@]}" --study-out "$out")
  machine "${cmd[*]}" > "$out/machine.txt"
  "${cmd[@]}" > "$out/progress.log"
}

fig6() {
  local out="$base/fig6_82k"
  # shellcheck disable=SC2046
  study "$out" $(helix_of 82k) --warmup 1 --frames 100 --every 1 --repeats 1 \
    --case "position:init=position" --case "velocity:init=velocity" \
    --case "constant_acceleration:init=constant_acceleration" --case "optimized:init=optimized"
  gzip -f "$out/study.csv"
  $PYTHON tools/plot_study.py "$out" --frames --title "Fig. 6: initialisations, helix 82K (AMG Newton truth)"
}

fig2c() {
  for preset in 158k 316k; do
    local out="$base/fig2c_$preset"
    # shellcheck disable=SC2046
    study "$out" $(helix_of "$preset") --warmup 10 --repeats 1 --case chebyshev \
      --case "chebyshev_fixed:$FIXED" --case gd --case jacobi_gd --case ncg --case lbfgs \
      --case nesterov --case "newton:method=newton newton_solver=petsc"
    $PYTHON tools/plot_study.py "$out" --title "Fig. 2c: methods, helix $preset (AMG Newton truth)" \
      --cases chebyshev chebyshev_fixed gd jacobi_gd ncg lbfgs nesterov newton --name fig2c
  done
}

pareto() {
  local out="$base/pareto/helix82k/np2"  # the layout tools/plot_pareto.py reads
  # shellcheck disable=SC2046
  study "$out" $(helix_of 82k) --warmup 10 --repeats 3 \
    --case "automatic:method=chebyshev iterations=700" --case "fixed:$FIXED iterations=400" \
    --case "ncg:method=ncg iterations=400" --case "lbfgs:method=lbfgs iterations=500" \
    --case "newton_amg:method=newton newton_solver=petsc"
  $PYTHON tools/plot_pareto.py "$base/pareto" --out "$base/pareto"
}

[ $# -gt 0 ] || set -- fig6 fig2c pareto
for figure in "$@"; do "$figure"; done
