#!/usr/bin/env bash
# A run that reaches a state with no finite energy must stop on every rank
# with a non-zero exit code, no hang, a message naming frame, rank and tet,
# the failed step in stats.csv, and the last good frame readable on disk.
# Usage: non_finite_stop.sh DESCENT READ_FRAME SCENE OUT_DIR NP
set -euo pipefail
descent=$1 read_frame=$2 scene=$3 out=$4 np=$5
rm -rf "$out" && mkdir -p "$out"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMP_NUM_THREADS=1
# Each rank records its own exit code (mpiexec alone reports only one), and a
# hang is cut off by the timeout.
timeout 120 mpiexec -n "$np" --oversubscribe sh -c \
  '"$0" run "$1" --out "$2/run" --quiet 2>"$2/err.$OMPI_COMM_WORLD_RANK"; echo $? >"$2/rc.$OMPI_COMM_WORLD_RANK"' \
  "$descent" "$scene" "$out"
fail() { echo "FAIL: $*"; cat "$out"/err.* "$out/run/stats.csv" 2>/dev/null; exit 1; }
for ((r = 0; r < np; ++r)); do
  [ -f "$out/rc.$r" ] || fail "rank $r left no exit code"
  [ "$(cat "$out/rc.$r")" != 0 ] || fail "rank $r exited 0"
done
cat "$out"/err.*
grep -qE "frame 3: no state with finite energy.* on rank [0-9]+ the energy of inverted tet [0-9]+ is inf" \
  "$out"/err.* || fail "no message naming frame 3, the rank and the tet"
[ "$(cat "$out"/err.* | grep -c 'error')" = 1 ] || fail "the error is not printed exactly once"
tail -n 1 "$out/run/stats.csv" | grep -q "^3,.*,failed_non_finite" || fail "stats.csv lacks the failed step"
"$read_frame" "$out/run/frames.h5" 2 || fail "the last good frame (2) is not on disk"
if "$read_frame" "$out/run/frames.h5" 3; then fail "the failed frame 3 was written"; fi
grep -q 'Time Value="0.2"' "$out/run/frames.xdmf" || fail "frames.xdmf does not list frame 2"
echo "PASS"
