#!/usr/bin/env bash
# Issue 22 part 3: which accuracy targets float meets on the CPU, and at what
# speed against double. The generated double helix of jobs/helix.toml at
# resolution RESOLUTION (default 1.5: 9K tets; the 82K preset with
# PRESET=82k), one rank, WARMUP frames of the scene's own method, then FRAMES
# measured steps of the default method (Chebyshev with its automatic
# preconditioner) at each target in TOLS, under a cap of CAP iterations, in
# double and in float. Each step starts from the state of the precision's own
# warm-up; its e is measured in double against Newton's eps* in double from
# that state (descent study's double twin), so float's round-off shows in e.
# Each case is timed REPEATS times (median). PRECONDITIONER=jacobi runs the
# papers' preconditioner instead of the scene's (its steps take hundreds of
# iterations, so the targets bind).
# Results in $PRECISION_RESULTS (default bench/results/precision/<size>/):
# (<size>: resolution_R or the preset, _jacobi with PRECONDITIONER=jacobi)
# double/ and float/ with ends.csv (each step's last record), accuracy.csv,
# progress.log, machine.txt; table.md beside them (tools/precision_table.py).
#   jobs/study/precision.sh
source "$(dirname "$0")/common.sh"
RESOLUTION=${RESOLUTION:-1.5}
WARMUP=${WARMUP:-5}
FRAMES=${FRAMES:-10}
TOLS=${TOLS:-"1e-2 1e-3 1e-4 1e-5"}
CAP=${CAP:-5000}
REPEATS=${REPEATS:-3}
if [ -n "${PRESET_SIZE:-}" ]; then
  size=$PRESET_SIZE
  mesh=(--set "mesh.helix.preset=\"$PRESET_SIZE\"")
else
  size=resolution_$RESOLUTION
  mesh=(--set "mesh.helix.resolution=$RESOLUTION")
fi
if [ -n "${PRECONDITIONER:-}" ]; then
  mesh+=(--set "solver.preconditioner=\"$PRECONDITIONER\"")
  size=${size}_$PRECONDITIONER
fi
base=${PRECISION_RESULTS:-bench/results/precision/$size}
mkdir -p "$base"

cases=()
for tol in $TOLS; do
  cases+=(--case "chebyshev_$tol:method=chebyshev accuracy=$tol iterations=$CAP")
done
for precision in double float; do
  study_ends "$base/$precision" $MPIEXEC -n 1 "$DESCENT" study jobs/helix.toml "${mesh[@]}" \
    "${TRUTH[@]}" --precision "$precision" --warmup "$WARMUP" --frames "$FRAMES" --every 1 \
    --repeats "$REPEATS" "${cases[@]}" --study-out "$base/$precision"
done
$PYTHON tools/precision_table.py "$base" > "$base/table.md"
cat "$base/table.md"
