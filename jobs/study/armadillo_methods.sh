#!/usr/bin/env bash
# Paper 1, Fig. 2c on a real mesh: the methods on the armadillo of
# ../shared/meshes (jobs/study/armadillo.toml); skipped with a message when
# that folder is absent.
#   jobs/study/armadillo_methods.sh
source "$(dirname "$0")/common.sh"
mesh=../shared/meshes/armadillo_10k.node
if [ ! -f "$mesh" ]; then
  echo "armadillo_methods.sh: $mesh not found (../shared/meshes absent): skipped" >&2
  exit 0
fi
out="$RESULTS/methods_armadillo"
mkdir -p "$out"
cmd=($MPIEXEC -n 1 "$DESCENT" study jobs/study/armadillo.toml "${JACOBI[@]}" "${TRUTH[@]}" --warmup 10 --repeats 3
     --case chebyshev --case "chebyshev_fixed:$FIXED" --case gd --case jacobi_gd --case ncg
     --case lbfgs --case nesterov --case newton --study-out "$out")
machine "${cmd[*]}" > "$out/machine.txt"
"${cmd[@]}" > >(tee "$out/progress.log")
$PYTHON tools/plot_study.py "$out" --title "Fig. 2c: methods, armadillo (55K tets)" --name fig2c
