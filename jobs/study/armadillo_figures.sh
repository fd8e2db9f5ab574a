#!/usr/bin/env bash
# Paper 1, Figs. 3-6 on a real mesh: the armadillo of ../shared/meshes
# (jobs/study/armadillo.toml; Fig. 2c is armadillo_methods.sh); skipped with a
# message when that folder is absent.
#  Fig. 3: Chebyshev with the Hessian diagonal every M = 1..32 iterations.
#  Fig. 4: chebyshev vs pd_chebyshev on the arap energy.
#  Fig. 5: Chebyshev with 1, 2, 4 tuned phases (Eq. 9, tuned here) vs Nesterov.
#  Every figure has Chebyshev with the automatic parameters (`chebyshev`) and
#  with the paper's fixed ones (`chebyshev_fixed`).
#  Fig. 6: the four initialisations; Newton per measured frame is the cost
#    (~1-2 min here), so 10 frames 10 apart span the 100-frame sequence.
#   jobs/study/armadillo_figures.sh
source "$(dirname "$0")/common.sh"
mesh=../shared/meshes/armadillo_10k.node
if [ ! -f "$mesh" ]; then
  echo "armadillo_figures.sh: $mesh not found (../shared/meshes absent): skipped" >&2
  exit 0
fi
scene=jobs/study/armadillo.toml
base="$RESULTS/armadillo_figures"
mkdir -p "$base"
study() {  # study OUT ARGS...: one descent study with its machine record
  local out=$1
  shift
  mkdir -p "$out"
  local cmd=($MPIEXEC -n 1 "$DESCENT" study "$@" "${JACOBI[@]}" --study-out "$out")
  machine "${cmd[*]}" > "$out/machine.txt"
  "${cmd[@]}" > "$out/progress.log"
}

cases=(--case chebyshev --case "chebyshev_fixed:$FIXED")
for m in 1 2 4 8 16 32; do cases+=(--case "M$m:method=chebyshev hessian_interval=$m"); done
for p in 1 2 4; do
  cmd=($MPIEXEC -n 1 "$DESCENT" tune "$scene" --phases "$p" --warmup 10 --frames 1 --max-cycles 30
       --tune-out "$base/tuned_P$p.toml")
  machine "${cmd[*]}" > "$base/tuned_P$p.machine.txt"
  "${cmd[@]}" 2> "$base/tuned_P$p.log"
  cases+=(--case "P$p:$(tuned_keys "$base/tuned_P$p.toml")")
done
study "$base/fig3_fig5" "$scene" "${TRUTH[@]}" --warmup 10 --repeats 3 "${cases[@]}" \
  --case nesterov --case newton
$PYTHON tools/plot_study.py "$base/fig3_fig5" --title "Fig. 3: Hessian diagonal every M, armadillo" \
  --cases M1 M2 M4 M8 M16 M32 --name fig3
$PYTHON tools/plot_study.py "$base/fig3_fig5" --title "Fig. 5: Chebyshev phases vs Nesterov, armadillo" \
  --cases chebyshev chebyshev_fixed P1 P2 P4 nesterov --name fig5

study "$base/fig4" "$scene" "${TRUTH[@]}" --set 'material.model="arap"' --warmup 10 --repeats 3 \
  --case chebyshev --case "chebyshev_fixed:$FIXED" --case pd_chebyshev \
  --case "chebyshev_M1:method=chebyshev hessian_interval=1" --case newton
$PYTHON tools/plot_study.py "$base/fig4" --title "Fig. 4: arap energy, armadillo" --name fig4

study "$base/fig6" "$scene" "${TRUTH[@]}" --warmup 1 --frames 10 --every 10 --repeats 1 \
  --case "position:init=position" --case "velocity:init=velocity" \
  --case "constant_acceleration:init=constant_acceleration" --case "optimized:init=optimized"
$PYTHON tools/plot_study.py "$base/fig6" --frames --title "Fig. 6: initialisations, armadillo"
