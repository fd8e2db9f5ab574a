#!/usr/bin/env bash
# Kill a real run after its first checkpoint, continue it with --restart, and
# require the final state to equal an uninterrupted run's bit for bit (the
# final checkpoints hold q, v, v_prev, alpha and interpolants of every rank).
#   restart.sh DESCENT SCENE OUT_DIR RANKS
set -euo pipefail
descent=$1 scene=$2 out=$3 ranks=$4
run() { mpiexec -n "$ranks" --oversubscribe "$descent" run "$scene" --quiet "$@"; }
rm -rf "$out"
run --out "$out/whole"

# In a session of its own, so the kill reaches mpiexec and every rank.
setsid mpiexec -n "$ranks" --oversubscribe "$descent" run "$scene" --quiet --out "$out/killed" &
pid=$!
first="$out/killed/checkpoint/rank-0-of-$ranks.bin"
for _ in $(seq 600); do [ -f "$first" ] && break; sleep 0.05; done
# Open MPI puts ranks in process groups of their own: kill the whole session.
[ -f "$first" ] || { echo "no checkpoint appeared"; pkill -9 -s $pid; exit 1; }
pkill -9 -s $pid
wait $pid 2>/dev/null || true
while pgrep -s $pid > /dev/null; do sleep 0.05; done
killed_after=$(($(wc -l < "$out/killed/stats.csv") - 1))
echo "killed after $killed_after frames"
[ "$killed_after" -lt 40 ] || { echo "the run finished before it was killed"; exit 1; }

run --out "$out/killed" --restart
for r in $(seq 0 $((ranks - 1))); do
  cmp "$out/whole/checkpoint/rank-$r-of-$ranks.bin" "$out/killed/checkpoint/rank-$r-of-$ranks.bin"
done
# The stats of the restarted run list every frame once.
[ "$(cut -d, -f1 "$out/killed/stats.csv" | tail -n +2 | tr '\n' ' ')" = "$(seq 1 40 | tr '\n' ' ')" ]
echo "restarted run equals the uninterrupted one bit for bit on $ranks rank(s)"
