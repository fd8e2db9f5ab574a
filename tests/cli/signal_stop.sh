#!/usr/bin/env bash
# SIGTERM to every rank of a run mid-way (as scancel and a time limit send
# it): every rank exits within 5 s with status 75, the checkpoint holds the
# last finished frame (the last row of stats.csv), and --restart ends bit
# for bit where an uninterrupted run ends.
#   signal_stop.sh DESCENT SCENE OUT_DIR RANKS
set -euo pipefail
descent=$1 scene=$2 out=$3 ranks=$4
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMP_NUM_THREADS=1
fail() { echo "FAIL: $*"; cat "$out"/err.* 2>/dev/null; exit 1; }
rm -rf "$out" && mkdir -p "$out"
mpiexec -n "$ranks" --oversubscribe "$descent" run "$scene" --quiet --out "$out/whole"

# Each rank records its pid and its own exit status (mpiexec reports one).
# The wrapper then waits (up to 10 s) for every rank's status before it
# exits: mpiexec takes a wrapper that ends while another rank still runs for
# a failed process and sends SIGTERM to the rest, wrappers included, and a
# rank's status would be lost (seen under load on 2 ranks).
mpiexec -n "$ranks" --oversubscribe sh -c \
  '"$0" run "$1" --quiet --out "$2/stopped" 2>"$2/err.$OMPI_COMM_WORLD_RANK" &
   echo $! >"$2/pid.$OMPI_COMM_WORLD_RANK"; wait $!; echo $? >"$2/rc.$OMPI_COMM_WORLD_RANK"
   for _ in $(seq 200); do [ "$(ls "$2" | grep -c "^rc\.")" -ge "$3" ] && break; sleep 0.05; done' \
  "$descent" "$scene" "$out" "$ranks" &
launcher=$!
stats="$out/stopped/stats.csv"
for _ in $(seq 600); do
  [ -f "$stats" ] && [ "$(wc -l <"$stats")" -ge 4 ] && break
  sleep 0.05
done
[ -f "$stats" ] && [ "$(wc -l <"$stats")" -ge 4 ] || fail "the run wrote no 3 frames"
sent=$(date +%s%N)
for ((r = 0; r < ranks; ++r)); do kill -TERM "$(cat "$out/pid.$r")"; done
for _ in $(seq 100); do
  [ "$(ls "$out" | grep -c '^rc\.')" = "$ranks" ] && break
  sleep 0.05
done
took_ms=$((($(date +%s%N) - sent) / 1000000))
wait $launcher || true
echo "all ranks exited ${took_ms} ms after SIGTERM"
for ((r = 0; r < ranks; ++r)); do
  [ -f "$out/rc.$r" ] || fail "rank $r had not exited 5 s after SIGTERM"
  [ "$(cat "$out/rc.$r")" = 75 ] || fail "rank $r exited $(cat "$out/rc.$r"), not 75"
done
grep -q "SIGTERM: stopped after frame [0-9]* of 40.*--restart --out $out/stopped" "$out"/err.* ||
  fail "no line saying where the run stopped and how to continue"

# The checkpoint's frame (int32 after the 21-byte magic, num_ranks and rank)
# is the last frame in stats.csv, on every rank.
last=$(tail -n 1 "$stats" | cut -d, -f1)
[ "$last" -lt 40 ] || fail "the run finished before the signal"
for ((r = 0; r < ranks; ++r)); do
  frame=$(od -An -t d4 -j 29 -N 4 "$out/stopped/checkpoint/rank-$r-of-$ranks.bin" | tr -d ' ')
  [ "$frame" = "$last" ] || fail "rank $r's checkpoint holds frame $frame, stats.csv ends at $last"
done
echo "stopped after frame $last; checkpoints of frame $last on all $ranks rank(s)"

mpiexec -n "$ranks" --oversubscribe "$descent" run "$scene" --quiet --out "$out/stopped" --restart
for ((r = 0; r < ranks; ++r)); do
  cmp "$out/whole/checkpoint/rank-$r-of-$ranks.bin" "$out/stopped/checkpoint/rank-$r-of-$ranks.bin"
done
[ "$(cut -d, -f1 "$stats" | tail -n +2 | tr '\n' ' ')" = "$(seq 1 40 | tr '\n' ' ')" ] ||
  fail "stats.csv does not list every frame once"
echo "PASS: the stopped run, restarted, equals the uninterrupted one bit for bit on $ranks rank(s)"
