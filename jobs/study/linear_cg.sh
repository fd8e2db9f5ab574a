#!/usr/bin/env bash
# Paper 2 (Dahl & Bargteil 2019) with our numbers, on the corotated helix
# (41k; the method needs the corotated model) and the armadillo when
# ../shared/meshes is present:
#  Table 1: ms/frame of linear_cg at 1, 2, 5, 10 CG iterations and at
#    convergence (r.r <= 1e-10 b.b) for the three initial guesses (Jacobi),
#    with the mean iterations to converge and each run's distance from the
#    converged run (guess v_t) over the whole sequence; chebyshev (96) beside.
#    At paper 1's h = 1/30 s and at paper 2's h = 1/150 s.
#  Fig. 3/4: kinetic energy over the CG iterations of one solve for every
#    guess and preconditioner (descent study, its `kinetic` column).
#   jobs/study/linear_cg.sh        (PRESET=41k by default here)
#   PRESET=82k PARTS=h30 jobs/study/linear_cg.sh   (only the h = 1/30 table)
# PARTS: any of h30 h150 kinetic armadillo (default all).
PRESET=${PRESET:-41k}
PARTS=${PARTS:-h30 h150 kinetic armadillo}
part() { [[ " $PARTS " == *" $1 "* ]]; }
source "$(dirname "$0")/common.sh"
corotated=(--set 'material.model="corotated"' --set 'solver.method="linear_cg"')

# Whether run directory $1 holds all $2 frames (a rerun skips it).
complete() { [ -f "$1/stats.csv" ] && [ "$(($(wc -l < "$1/stats.csv") - 1))" -ge "$2" ]; }

# Table 1: runs of FRAMES frames, one per guess and budget, into $1/NAME.
table() {
  local out=$1 frames=$2
  shift 2
  local scene=("$@")
  mkdir -p "$out"
  machine "(one run per guess and budget) $DESCENT run ${scene[*]} ${corotated[*]}" >> "$out/machine.txt"
  for guess in zero velocity euler; do
    for budget in 1 2 5 10 conv; do
      local its=$budget
      [ "$budget" = conv ] && its=100000
      if complete "$out/${guess}_$budget" "$frames"; then continue; fi
      echo "linear_cg.sh: $out: guess $guess, budget $budget" >&2
      # An unstable guess/budget may blow up: the run then stops naming the
      # tet, and the table says where.
      $MPIEXEC -n 1 "$DESCENT" run "${scene[@]}" "${corotated[@]}" --overwrite \
        --set "time.frames=$frames" --set "solver.iterations=$its" \
        --set "solver.linear_cg_guess=\"$guess\"" --set "output.dir=\"$out/${guess}_$budget\"" \
        --set "output.checkpoint_every=0" > "$out/${guess}_$budget.log" 2>&1 ||
        echo "linear_cg.sh: $out/${guess}_$budget stopped (see its .log)" >&2
    done
  done
}

if part h30; then
  table "$RESULTS/linear_cg_${PRESET}/h30" 30 "${helix[@]}"
  echo "linear_cg.sh: chebyshev beside (h = 1/30)" >&2
  complete "$RESULTS/linear_cg_${PRESET}/h30/chebyshev" 30 ||
    $MPIEXEC -n 1 "$DESCENT" run "${helix[@]}" --set 'material.model="corotated"' --overwrite \
      --set time.frames=30 --set "output.dir=\"$RESULTS/linear_cg_${PRESET}/h30/chebyshev\"" \
      --set "output.checkpoint_every=0" > "$RESULTS/linear_cg_${PRESET}/h30/chebyshev.log"
  $PYTHON tools/linear_cg_table.py "$RESULTS/linear_cg_${PRESET}/h30" \
    > "$RESULTS/linear_cg_${PRESET}/h30/table1.md"
fi
if part h150; then
  table "$RESULTS/linear_cg_${PRESET}/h150" 150 "${helix[@]}" --set "time.dt=$(echo 'print(1/150)' | $PYTHON)"
  $PYTHON tools/linear_cg_table.py "$RESULTS/linear_cg_${PRESET}/h150" \
    > "$RESULTS/linear_cg_${PRESET}/h150/table1.md"
fi

# Fig. 3/4: one solve after 10 frames, every guess x preconditioner.
if part kinetic; then
  out="$RESULTS/linear_cg_${PRESET}/kinetic"
  mkdir -p "$out"
  cases=(--case newton)
  for p in identity mass jacobi; do
    for guess in zero velocity euler; do
      cases+=(--case "${p}_${guess}:method=linear_cg linear_cg_preconditioner=\"$p\" linear_cg_guess=\"$guess\" iterations=400")
    done
  done
  cmd=($MPIEXEC -n 1 "$DESCENT" study "${helix[@]}" "${corotated[@]}" --warmup 10 --repeats 3
       "${cases[@]}" --study-out "$out")
  machine "${cmd[*]}" > "$out/machine.txt"
  "${cmd[@]}" > "$out/progress.log"
  $PYTHON tools/plot_kinetic.py "$out" --title "linear_cg, one solve, helix $PRESET (corotated, h = 1/30 s)"
fi
part armadillo || exit 0

mesh=../shared/meshes/armadillo_10k.node
if [ ! -f "$mesh" ]; then
  echo "linear_cg.sh: $mesh not found (../shared/meshes absent): armadillo skipped" >&2
  exit 0
fi
table "$RESULTS/linear_cg_armadillo/h30" 30 jobs/study/armadillo.toml
$PYTHON tools/linear_cg_table.py "$RESULTS/linear_cg_armadillo/h30" \
  > "$RESULTS/linear_cg_armadillo/h30/table1.md"
