#!/usr/bin/env bash
# Distributed cost: Chebyshev vs NCG (and L-BFGS) on 1, 2, 4 ranks: time in
# MPI_Allreduce per iteration and the time to reach e = 1e-3 (longer budgets
# too, since 96 iterations may not reach it). Newton per rank count is the
# cost, hence the 41k helix by default. On 2 cores, 4 ranks are
# oversubscribed: their times measure contention, not scaling.
# MODEL=corotated runs the same on the corotated helix with paper 2's
# linear_cg beside (Jacobi, guess v_t, to convergence or 400 iterations).
#   jobs/study/distributed.sh              (PRESET=41k by default here)
#   MODEL=corotated jobs/study/distributed.sh
PRESET=${PRESET:-41k}
MODEL=${MODEL:-neo_hookean}
source "$(dirname "$0")/common.sh"
name="distributed_${PRESET}"
cases=(--case chebyshev --case ncg --case lbfgs --case "chebyshev_480:method=chebyshev iterations=480"
       --case "ncg_192:method=ncg iterations=192")
if [ "$MODEL" != neo_hookean ]; then
  name="${name}_${MODEL}"
  helix+=(--set "material.model=\"$MODEL\"")
  cases=(--case chebyshev --case ncg --case "ncg_192:method=ncg iterations=192"
         --case "linear_cg:method=linear_cg iterations=400")
fi
for np in 1 2 4; do
  out="$RESULTS/$name/np$np"
  mkdir -p "$out"
  cmd=($MPIEXEC -n "$np" "$DESCENT" study "${helix[@]}" --warmup 10 --repeats 3
       "${cases[@]}" --study-out "$out")
  machine "${cmd[*]}" > "$out/machine.txt"
  "${cmd[@]}" > "$out/progress.log"
done
$PYTHON tools/plot_study.py "$RESULTS/$name"/np* \
  --out "$RESULTS/$name" --title "Distributed cost, helix $PRESET ($MODEL)"
$PYTHON tools/distributed_summary.py "$RESULTS/$name"/np* > "$RESULTS/$name/summary.md"
