#!/usr/bin/env bash
# A scene with no solver keys runs each step to the default accuracy: every
# frame's estimated relative error (stats.csv) is finite and at most 1e-2,
# and the target, not the cap, ended each step.
#   default_accuracy.sh DESCENT SCENE OUT_DIR RANKS
set -euo pipefail
descent=$1 scene=$2 out=$3 ranks=$4
rm -rf "$out"
mpiexec -n "$ranks" --oversubscribe "$descent" run "$scene" --quiet --out "$out"
awk -F, '
  NR == 1 { for (i = 1; i <= NF; ++i) column[$i] = i; next }
  {
    e = $column["error_estimate"]; k = $column["iterations"]
    printf "frame %s: %s iterations, estimated error %s\n", $column["frame"], k, e
    if (e !~ /^[0-9.eE+-]+$/ || e + 0 > 1e-2) { print "above the default target 1e-2"; bad = 1 }
    if (k + 0 >= 1000) { print "the cap ended the step"; bad = 1 }
    ++rows
  }
  END { if (rows != 4) { print "expected 4 frames, got " rows; bad = 1 } exit bad }
' "$out/stats.csv"
