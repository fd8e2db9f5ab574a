#!/usr/bin/env bash
# Our ncg and lbfgs against PETSc TAO's bncg and blmvm (docs/tao.md) on the
# same eps, gradient and initial guess, in one study per mesh and rank count
# (one Newton eps*): the 41K helix and the armadillo of ../shared/meshes
# (skipped with a message when absent), on 1 and 2 ranks. Each case runs
# ITERATIONS iterations (default 500: enough for 1e-4 on the helix) unless
# its |g| reaches 1e-10 |g0| first. Needs a build with PETSc.
#   jobs/study/tao_peers.sh   (RESULTS=bench/results MESHES="helix armadillo" NPS="1 2"
#                              ITERATIONS=500 WARMUP=10 REPEATS=3 PRESET=41k)
# (before common.sh, whose defaults are the 82K helix and bench/results/study)
PRESET=${PRESET:-41k}
RESULTS=${RESULTS:-bench/results}
source "$(dirname "$0")/common.sh"
ITERATIONS=${ITERATIONS:-500}
NPS=${NPS:-1 2}
WARMUP=${WARMUP:-10}
REPEATS=${REPEATS:-3}
base="$RESULTS/tao_peers"
cases=()
for m in ncg lbfgs tao_bncg tao_blmvm; do cases+=(--case "$m:method=$m iterations=$ITERATIONS"); done
# Newton's eps* by the direct solver (the study's --truth-solver where this
# build has it; the scene key otherwise).
truth=("${TRUTH[@]}")
if "$DESCENT" study --help 2>/dev/null | grep -q -- --truth-solver; then
  truth+=(--truth-solver ldlt)
fi
armadillo=../shared/meshes/armadillo_10k.node
meshes=()
for mesh in ${MESHES:-helix armadillo}; do
  if [ "$mesh" = armadillo ] && [ ! -f "$armadillo" ]; then
    echo "tao_peers.sh: $armadillo not found (../shared/meshes absent): armadillo skipped" >&2
    continue
  fi
  meshes+=("$mesh")
done
for mesh in "${meshes[@]}"; do
  if [ "$mesh" = helix ]; then
    # The warm-up (the scene's Chebyshev) at the cap too, as the helix ran.
    scene=(jobs/helix.toml --set "mesh.helix.preset=\"${PRESET}\"" --set solver.accuracy=0
           --set solver.iterations="$ITERATIONS" "${JACOBI[@]}")
    name="helix_$PRESET"
  else
    # The warm-up at the scene's 96 iterations: at 500 per frame the
    # armadillo's Chebyshev warm-up reached a non-finite state (eps* NaN).
    scene=(jobs/study/armadillo.toml "${JACOBI[@]}")
    name=armadillo
  fi
  for np in $NPS; do
    out="$base/${name}_np$np"
    mkdir -p "$out"
    cmd=($MPIEXEC -n "$np" "$DESCENT" study "${scene[@]}" "${truth[@]}" --warmup "$WARMUP" --repeats "$REPEATS" "${cases[@]}" --study-out "$out")
    machine "${cmd[*]}" > "$out/machine.txt"
    "${cmd[@]}" > >(tee "$out/progress.log")
    $PYTHON tools/plot_study.py "$out" --title "ours vs PETSc TAO, $name, $np rank(s)" --name tao_peers
    # Rank 0's processor time: on a shared machine less of the other jobs' load.
    $PYTHON tools/plot_study.py "$out" --title "ours vs PETSc TAO, $name, $np rank(s), processor time" \
      --name tao_peers_cpu --time cpu
  done
done
