#!/usr/bin/env bash
# Paper 1, Eq. 9: tuned fixed Chebyshev parameters for the helix, P = 1, 2
# and 4 phases (descent tune's compass search in log(1 - rho) and alpha),
# written as scene keys to $RESULTS/tuned_P{1,2,4}.toml (used by
# descent_methods.sh), each with the automatic parameters' cost beside.
# At most 30 cycles: each costs 2P + 2 + 2(P - 1) pre-simulated steps.
#   jobs/study/tune_phases.sh       (PHASES="2 4" for some of them)
source "$(dirname "$0")/common.sh"
mkdir -p "$RESULTS"
for p in ${PHASES:-1 2 4}; do
  cmd=($MPIEXEC -n 1 "$DESCENT" tune "${helix[@]}" --phases "$p" --warmup 10 --frames 1 --max-cycles 30
       --tune-out "$RESULTS/tuned_P$p.toml")
  machine "${cmd[*]}" > "$RESULTS/tuned_P$p.machine.txt"
  "${cmd[@]}" 2> "$RESULTS/tuned_P$p.log"
done
