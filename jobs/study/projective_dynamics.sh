#!/usr/bin/env bash
# Paper 1, Fig. 4: Chebyshev descent against Chebyshev-accelerated Jacobi
# projective dynamics (Wang 2015) on the same arap energy, with the same rho,
# delay and step control; plus Chebyshev with the diagonal every iteration.
#   jobs/study/projective_dynamics.sh      (PRESET=41k for the smaller helix)
source "$(dirname "$0")/common.sh"
out="$RESULTS/projective_dynamics_${PRESET}"
mkdir -p "$out"
cmd=($MPIEXEC -n 1 "$DESCENT" study "${helix[@]}" "${TRUTH[@]}" --set 'material.model="arap"'
     --warmup 10 --repeats 3 --case chebyshev --case "chebyshev_fixed:$FIXED" --case pd_chebyshev
     --case "chebyshev_M1:method=chebyshev hessian_interval=1" --case newton --study-out "$out")
machine "${cmd[*]}" > "$out/machine.txt"
"${cmd[@]}" > >(tee "$out/progress.log")
$PYTHON tools/plot_study.py "$out" --title "Fig. 4: arap energy, helix $PRESET" --name fig4
