#!/usr/bin/env bash
# Paper 1, Fig. 6: the four initialisations over a 100-frame sequence, the error
# at the end of each step against that frame's Newton eps*. Newton per frame
# is the cost: the small helix of jobs/study/small_helix.toml (~5K tets).
#   jobs/study/initialisations.sh
source "$(dirname "$0")/common.sh"
out="$RESULTS/initialisations"
mkdir -p "$out"
cmd=($MPIEXEC -n 1 "$DESCENT" study jobs/study/small_helix.toml "${JACOBI[@]}" "${TRUTH[@]}"
     --warmup 1 --frames 100 --every 1 --repeats 1
     --case "position:init=position" --case "velocity:init=velocity"
     --case "constant_acceleration:init=constant_acceleration" --case "optimized:init=optimized"
     --study-out "$out")
machine "${cmd[*]}" > "$out/machine.txt"
"${cmd[@]}" > "$out/progress.log"
$PYTHON tools/plot_study.py "$out" --frames --title "Fig. 6: initialisations, small helix"
