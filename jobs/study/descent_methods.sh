#!/usr/bin/env bash
# Paper 1, Figs. 2c, 3 and 5 on the helix in one study (one Newton eps*):
# the methods, Chebyshev with the automatic parameters and with the paper's
# fixed ones; the automatic Chebyshev with M = 1..32; Chebyshev with 1, 2, 4
# tuned phases (tune_phases.sh first, else those cases are left out)
# against Nesterov.
#   jobs/study/descent_methods.sh          (PRESET=41k for the smaller helix)
source "$(dirname "$0")/common.sh"
out="$RESULTS/methods_${PRESET}"
mkdir -p "$out"
cases=(--case chebyshev --case "chebyshev_fixed:$FIXED" --case gd --case jacobi_gd --case ncg
       --case lbfgs --case nesterov --case newton)
for m in 1 2 4 8 16 32; do cases+=(--case "M$m:method=chebyshev hessian_interval=$m"); done
# Tuned phases (descent tune's keys to case keys).
for p in 1 2 4; do
  f="$RESULTS/tuned_P$p.toml"
  [ -f "$f" ] || { echo "no $f: run jobs/study/tune_phases.sh for the phase cases" >&2; continue; }
  cases+=(--case "P$p:$(tuned_keys "$f")")
done
cmd=($MPIEXEC -n 1 "$DESCENT" study "${helix[@]}" "${TRUTH[@]}" --warmup 10 --repeats 3
     "${cases[@]}" --study-out "$out")
machine "${cmd[*]}" > "$out/machine.txt"
"${cmd[@]}" > >(tee "$out/progress.log")
$PYTHON tools/plot_study.py "$out" --title "Fig. 2c: methods, helix $PRESET" \
  --cases chebyshev chebyshev_fixed gd jacobi_gd ncg lbfgs nesterov newton --name fig2c
$PYTHON tools/plot_study.py "$out" --title "Fig. 2c: methods, helix $PRESET (processor time)" \
  --cases chebyshev chebyshev_fixed gd jacobi_gd ncg lbfgs nesterov newton --name fig2c_cpu \
  --time cpu
$PYTHON tools/plot_study.py "$out" --title "Fig. 3: Hessian diagonal every M, helix $PRESET" \
  --cases M1 M2 M4 M8 M16 M32 --name fig3
$PYTHON tools/plot_study.py "$out" --title "Fig. 5: Chebyshev phases vs Nesterov, helix $PRESET" \
  --cases chebyshev chebyshev_fixed P1 P2 P4 nesterov --name fig5
