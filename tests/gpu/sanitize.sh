#!/usr/bin/env bash
# compute-sanitizer --tool TOOL over one rank of `descent run SCENE` on the
# CUDA backend, in float and double, gather and scatter.
#   sanitize.sh memcheck|racecheck DESCENT SCENE OUTDIR
# Exit 77 (ctest: skipped) with the reason when compute-sanitizer or a usable
# device is missing; 1 when the sanitizer reports an error.
set -uo pipefail
tool=$1 descent=$2 scene=$3 out=$4
sanitizer=$(command -v compute-sanitizer || true)
for d in "${CUDA_HOME:-}" /usr/local/cuda; do
  [ -n "$sanitizer" ] || [ -z "$d" ] || [ ! -x "$d/bin/compute-sanitizer" ] || sanitizer=$d/bin/compute-sanitizer
done
if [ -z "$sanitizer" ]; then
  echo "skipped: compute-sanitizer not found (PATH, CUDA_HOME, /usr/local/cuda/bin)"
  exit 77
fi
if ! "$descent" --version | grep -q '^device 0:'; then
  echo "skipped: no usable CUDA device:"
  "$descent" --version
  exit 77
fi
status=0
for precision in float double; do
  for assembly in gather scatter; do
    echo "== compute-sanitizer --tool $tool: $precision, $assembly"
    "$sanitizer" --tool "$tool" --error-exitcode 1 --print-limit 20 \
      "$descent" run "$scene" --backend cuda --precision "$precision" --assembly "$assembly" \
      --overwrite --quiet --out "$out/$precision-$assembly" || status=1
  done
done
exit $status
