#!/usr/bin/env bash
# Binary files that cannot hurt a run: partition files, checkpoints and
# frames.h5 that descent wrote, each broken one way (tests/cli/break_h5.py,
# bytes flipped, truncated, moved), end every rank with exit 1 and one
# "descent: error:" line naming the file and what is wrong, within a timeout
# (a hang fails), and never with HDF5's own error stack. A checkpoint set
# whose newer files are damaged restarts from .prev and ends bit for bit
# where the uninterrupted run ends.
#   binary_inputs.sh DESCENT OUT_DIR RANKS BREAK_H5_PY
#
# The failing runs are independent and spend their time starting MPI, not
# computing, so each group of them runs at once (start_case), then is
# checked (check_cases).
set -euo pipefail
descent=$1 out=$2 ranks=$3 break_h5=$4
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMP_NUM_THREADS=1
rm -rf "$out" && mkdir -p "$out/cases"
fail() { echo "FAIL: $*"; exit 1; }
mpi() { timeout 120 mpiexec -n "$ranks" --oversubscribe "$descent" "$@"; }
cases=()
# start_case NAME REGEX COMMAND...: runs COMMAND in the background; its exit
# status, stdout and stderr go to $out/cases/NAME.*.
start_case() {
  local name=$1 regex=$2
  shift 2
  echo "$regex" >"$out/cases/$name.regex"
  (
    code=0
    mpi "$@" >"$out/cases/$name.stdout" 2>"$out/cases/$name.stderr" || code=$?
    echo "$code" >"$out/cases/$name.code"
  ) &
  cases+=("$name")
}
# check_cases: waits for the started cases; each must exit 1 (124: a hang)
# with one "descent: error:" line matching its REGEX and no library trace.
check_cases() {
  wait
  local name regex
  for name in "${cases[@]}"; do
    regex=$(cat "$out/cases/$name.regex")
    echo "--- $name"
    cat "$out/cases/$name.stderr"
    [ "$(cat "$out/cases/$name.code")" = 1 ] || fail "$name: exit $(cat "$out/cases/$name.code"), not 1"
    grep -qE "^descent: error: .*$regex" "$out/cases/$name.stderr" ||
      fail "$name: stderr does not match '$regex'"
    [ "$(grep -c '^descent: error:' "$out/cases/$name.stderr")" = 1 ] ||
      fail "$name: not exactly one error line"
    if grep -qE 'HDF5-DIAG|MPI_ABORT|H5[A-Z][a-z]*\(\)' "$out/cases/$name.stderr"; then
      fail "$name: a raw library trace"
    fi
  done
  cases=()
}
flip_two_bytes() {  # flip_two_bytes FILE...: two bytes in the middle of each file
  /usr/bin/python3 -c "
import sys
for p in sys.argv[1:]:
    b = bytearray(open(p, 'rb').read()); k = len(b) // 2
    b[k] ^= 0x40; b[k + 1] ^= 0x04; open(p, 'wb').write(b)" "$@"
}

cat >"$out/box.toml" <<'TOML'
[mesh]
generator = "box"
[mesh.box]
cells = [3, 2, 2]
size = [1.5, 1.0, 1.0]
TOML
"$descent" mesh "$out/box.toml" -o "$out/box.mesh" >/dev/null
cat >"$out/scene.toml" <<TOML
gravity = [0.0, -9.81, 0.0]
[mesh]
file = "$out/box.mesh"
[[fixed]]
box_min = [-1.0, 0.9, -1.0]
box_max = [2.0, 2.0, 2.0]
[time]
frames = 6
[solver]
iterations = 16
[output]
checkpoint_every = 2
TOML

# The intact partition file runs; the whole run writes checkpoints of frames
# 2, 4, 6 (6 and its .prev, 4, kept) and frames.h5.
mpi partition "$out/scene.toml" -n "$ranks" -o "$out/pieces.h5" --quiet >/dev/null
mpi run "$out/scene.toml" --partition "$out/pieces.h5" --quiet --out "$out/pieces_run" ||
  fail "the intact partition file does not run"
mpi run "$out/scene.toml" --quiet --out "$out/whole"

# Partition files.
broken=(offsets_past_end offsets_decreasing no_offsets tet_twice vertex_out_of_range num_parts
  float_ids nan_position surface_bits method stats short_tets)
mkdir -p "$out/broken"
/usr/bin/python3 "$break_h5" "$out/pieces.h5" "$out/broken" "${broken[@]}"
partition_case() {  # partition_case CASE REGEX
  start_case "$1" "broken/$1.h5.*$2" run "$out/scene.toml" --partition "$out/broken/$1.h5" \
    --quiet --overwrite --out "$out/run_$1"
}
partition_case offsets_past_end "dataset /partition/tet_offsets: row $ranks: .*past the end of /partition/tet_ids"
partition_case offsets_decreasing "dataset /partition/tet_offsets: row $ranks: .*less than the row before"
partition_case no_offsets "no dataset /partition/tet_offsets"
partition_case tet_twice "dataset /partition/tet_ids: row [0-9]+: tet [0-9]+ (again|after tet)"
partition_case vertex_out_of_range "dataset /partition/tets: row 0: vertex [0-9]+, but the mesh has"
partition_case num_parts "holds a partition into $((ranks + 1)) parts"
partition_case float_ids "/partition/tet_ids does not hold integers"
partition_case nan_position "dataset /mesh/positions: row 0: a non-finite coordinate"
partition_case surface_bits "dataset /partition/surface_faces: row 0: 200 is not"
partition_case method "attribute method: 'scotch', not metis, ptscotch or rcb"
partition_case stats "dataset /partition/part_stats: row 0: "
partition_case short_tets "dataset /partition/tets has [0-9]+ rows, but /partition/tet_ids has"
check_cases

# Checkpoints and the frame file of a restart, each case in a copy of the
# whole run.
ckpt() { echo "$out/$1/checkpoint/rank-$2-of-$ranks.bin"; }
fresh() { rm -rf "$out/$1" && cp -r "$out/whole" "$out/$1"; }
restart_case() {  # restart_case NAME REGEX: --restart in the copy NAME
  start_case "$1" "$2" run "$out/scene.toml" --quiet --out "$out/$1" --restart
}
last=$((ranks - 1))

fresh flipped_all
for r in $(seq 0 "$last"); do flip_two_bytes "$(ckpt flipped_all "$r")" "$(ckpt flipped_all "$r").prev"; done
restart_case flipped_all "rank-0-of-$ranks.bin is damaged: its checksum does not match"

fresh truncated
head -c 100 "$(ckpt whole 0)" >"$(ckpt truncated 0)"
rm "$(ckpt truncated 0).prev"
restart_case truncated "rank-0-of-$ranks.bin is truncated"

fresh empty
: >"$(ckpt empty 0)"
rm "$(ckpt empty 0).prev"
restart_case empty "rank-0-of-$ranks.bin is empty"

fresh missing
rm "$(ckpt missing "$last")" "$(ckpt missing "$last").prev"
if [ "$ranks" -gt 1 ]; then
  restart_case missing "rank-$last-of-$ranks.bin is missing"
  fresh other_rank
  cp "$(ckpt whole 1)" "$(ckpt other_rank 0)"
  rm "$(ckpt other_rank 0).prev"
  restart_case other_rank "rank-0-of-$ranks.bin holds the state of rank 1 of $ranks, not of rank 0"
else
  restart_case missing "holds no checkpoint"
fi

/usr/bin/python3 "$break_h5" "$out/whole/frames.h5" "$out/broken" frames_no_velocity frames_time_nan
fresh frames_no_velocity
cp "$out/broken/frames_no_velocity.h5" "$out/frames_no_velocity/frames.h5"
restart_case frames_no_velocity "no dataset /frames/000000/velocity"
fresh frames_time_nan
cp "$out/broken/frames_time_nan.h5" "$out/frames_time_nan/frames.h5"
restart_case frames_time_nan "frames.h5:/frames/000000: attribute time is not finite"

# Only the newer checkpoints damaged: the run continues from .prev, says so,
# and ends where the uninterrupted run ends, bit for bit.
fresh flipped_newer
for r in $(seq 0 "$last"); do flip_two_bytes "$(ckpt flipped_newer "$r")"; done
code=0
mpi run "$out/scene.toml" --quiet --out "$out/flipped_newer" --restart 2>"$out/flipped_newer.stderr" ||
  code=$?
check_cases
echo "--- flipped_newer"
cat "$out/flipped_newer.stderr"
[ "$code" = 0 ] || fail "a restart from intact .prev files failed (exit $code)"
grep -qE "^descent: warning: --restart: .*rank-0-of-$ranks.bin is damaged.*continuing after frame 4" \
  "$out/flipped_newer.stderr" || fail "the fallback to .prev is not explained on stderr"
for r in $(seq 0 "$last"); do
  cmp "$(ckpt whole "$r")" "$(ckpt flipped_newer "$r")" ||
    fail "the run restarted from .prev differs from the uninterrupted one (rank $r)"
done
echo "PASS: broken partition files, checkpoints and frame files refused cleanly on $ranks rank(s)"
