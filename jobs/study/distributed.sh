#!/usr/bin/env bash
# Distributed cost: Chebyshev vs NCG (and L-BFGS) on 1, 2, 4 ranks: time in
# MPI_Allreduce per iteration and the time to reach e = 1e-3 (longer budgets
# too, since 96 iterations may not reach it). Newton per rank count is the
# cost, hence the 41k helix by default. On 2 cores, 4 ranks are
# oversubscribed: their times measure contention, not scaling.
#   jobs/study/distributed.sh              (PRESET=41k by default here)
PRESET=${PRESET:-41k}
source "$(dirname "$0")/common.sh"
for np in 1 2 4; do
  out="$RESULTS/distributed_${PRESET}/np$np"
  mkdir -p "$out"
  cmd=($MPIEXEC -n "$np" "$DESCENT" study "${helix[@]}" --warmup 10 --repeats 3
       --case chebyshev --case ncg --case lbfgs --case "chebyshev_480:method=chebyshev iterations=480"
       --case "ncg_192:method=ncg iterations=192" --study-out "$out")
  machine "${cmd[*]}" > "$out/machine.txt"
  "${cmd[@]}" 2> "$out/progress.log"
done
$PYTHON tools/plot_study.py "$RESULTS/distributed_${PRESET}"/np* \
  --out "$RESULTS/distributed_${PRESET}" --title "Distributed cost, helix $PRESET"
$PYTHON tools/distributed_summary.py "$RESULTS/distributed_${PRESET}"/np* \
  > "$RESULTS/distributed_${PRESET}/summary.md"
