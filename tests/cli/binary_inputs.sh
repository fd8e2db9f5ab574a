#!/usr/bin/env bash
# Binary files that cannot hurt a run: partition files, checkpoints and
# frames.h5 that descent wrote, each broken one way (tests/cli/break_h5.py,
# bytes flipped, truncated, moved), end every rank with exit 1 and one
# "descent: error:" line naming the file and what is wrong, within a timeout
# (a hang fails), and never with HDF5's own error stack. A checkpoint set
# whose newer files are damaged restarts from .prev and ends bit for bit
# where the uninterrupted run ends.
#   binary_inputs.sh DESCENT OUT_DIR RANKS BREAK_H5_PY
set -euo pipefail
descent=$1 out=$2 ranks=$3 break_h5=$4
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMP_NUM_THREADS=1
rm -rf "$out" && mkdir -p "$out"
fail() { echo "FAIL: $*"; exit 1; }
mpi() { timeout 120 mpiexec -n "$ranks" --oversubscribe "$descent" "$@"; }
# expect_error REGEX COMMAND...: exit 1, REGEX in a "descent: error:" line, no
# HDF5 trace, no abort.
expect_error() {
  local regex=$1 code=0
  shift
  mpi "$@" >"$out/stdout" 2>"$out/stderr" || code=$?
  cat "$out/stderr"
  [ "$code" = 1 ] || fail "exit $code, not 1 (124: a hang), for $*"
  grep -qE "^descent: error: .*$regex" "$out/stderr" || fail "stderr does not match '$regex'"
  [ "$(grep -c '^descent: error:' "$out/stderr")" = 1 ] || fail "not exactly one error line"
  if grep -qE 'HDF5-DIAG|MPI_ABORT|H5[A-Z][a-z]*\(\)' "$out/stderr"; then fail "a raw library trace"; fi
}
flip_two_bytes() {  # flip_two_bytes FILE: two bytes in the middle of the payload
  /usr/bin/python3 -c "
import sys; p = sys.argv[1]; b = bytearray(open(p, 'rb').read()); k = len(b) // 2
b[k] ^= 0x40; b[k + 1] ^= 0x04; open(p, 'wb').write(b)" "$1"
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

# Partition files.
mpi partition "$out/scene.toml" -n "$ranks" -o "$out/pieces.h5" --quiet >/dev/null
mpi run "$out/scene.toml" --partition "$out/pieces.h5" --quiet --out "$out/pieces_run" ||
  fail "the intact partition file does not run"
cases=(offsets_past_end offsets_decreasing no_offsets tet_twice vertex_out_of_range num_parts
  float_ids nan_position surface_bits method stats short_tets)
mkdir -p "$out/broken"
/usr/bin/python3 "$break_h5" "$out/pieces.h5" "$out/broken" "${cases[@]}"
check_partition() {  # check_partition CASE REGEX
  echo "--- partition file: $1"
  expect_error "broken/$1.h5.*$2" run "$out/scene.toml" --partition "$out/broken/$1.h5" --quiet \
    --overwrite --out "$out/broken_run"
}
check_partition offsets_past_end "dataset /partition/tet_offsets: row $ranks: .*past the end of /partition/tet_ids"
check_partition offsets_decreasing "dataset /partition/tet_offsets: row $ranks: .*less than the row before"
check_partition no_offsets "no dataset /partition/tet_offsets"
check_partition tet_twice "dataset /partition/tet_ids: row [0-9]+: tet [0-9]+ (again|after tet)"
check_partition vertex_out_of_range "dataset /partition/tets: row 0: vertex [0-9]+, but the mesh has"
check_partition num_parts "holds a partition into $((ranks + 1)) parts"
check_partition float_ids "/partition/tet_ids does not hold integers"
check_partition nan_position "dataset /mesh/positions: row 0: a non-finite coordinate"
check_partition surface_bits "dataset /partition/surface_faces: row 0: 200 is not"
check_partition method "attribute method: 'scotch', not metis or ptscotch"
check_partition stats "dataset /partition/part_stats: row 0: "
check_partition short_tets "dataset /partition/tets has [0-9]+ rows, but /partition/tet_ids has"

# Checkpoints: the whole run writes frames 2, 4, 6 (6 and its .prev, 4, kept).
mpi run "$out/scene.toml" --quiet --out "$out/whole"
ckpt() { echo "$1/checkpoint/rank-$2-of-$ranks.bin"; }
fresh() {  # fresh NAME: a copy of the whole run to break
  rm -rf "$out/$1" && cp -r "$out/whole" "$out/$1"
  echo "--- checkpoints: $1"
}
restart() { mpi run "$out/scene.toml" --quiet --out "$out/$1" --restart; }

fresh flipped_all
for r in $(seq 0 $((ranks - 1))); do
  flip_two_bytes "$(ckpt "$out/flipped_all" "$r")"
  flip_two_bytes "$(ckpt "$out/flipped_all" "$r").prev"
done
expect_error "rank-0-of-$ranks.bin is damaged: its checksum does not match" \
  run "$out/scene.toml" --quiet --out "$out/flipped_all" --restart

fresh flipped_newer
for r in $(seq 0 $((ranks - 1))); do flip_two_bytes "$(ckpt "$out/flipped_newer" "$r")"; done
restart flipped_newer 2>"$out/stderr" || fail "a restart from intact .prev files failed"
cat "$out/stderr"
grep -qE "^descent: warning: --restart: .*rank-0-of-$ranks.bin is damaged.*continuing after frame 4" \
  "$out/stderr" || fail "the fallback to .prev is not explained on stderr"
for r in $(seq 0 $((ranks - 1))); do
  cmp "$(ckpt "$out/whole" "$r")" "$(ckpt "$out/flipped_newer" "$r")" ||
    fail "the run restarted from .prev differs from the uninterrupted one (rank $r)"
done

fresh truncated
head -c 100 "$(ckpt "$out/whole" 0)" >"$(ckpt "$out/truncated" 0)"
rm "$(ckpt "$out/truncated" 0).prev"
expect_error "rank-0-of-$ranks.bin is truncated" run "$out/scene.toml" --quiet \
  --out "$out/truncated" --restart

fresh empty
: >"$(ckpt "$out/empty" 0)"
rm "$(ckpt "$out/empty" 0).prev"
expect_error "rank-0-of-$ranks.bin is empty" run "$out/scene.toml" --quiet --out "$out/empty" --restart

last=$((ranks - 1))
fresh missing
rm "$(ckpt "$out/missing" "$last")" "$(ckpt "$out/missing" "$last").prev"
if [ "$ranks" -gt 1 ]; then
  expect_error "rank-$last-of-$ranks.bin is missing" run "$out/scene.toml" --quiet \
    --out "$out/missing" --restart
  fresh other_rank
  cp "$(ckpt "$out/whole" 1)" "$(ckpt "$out/other_rank" 0)"
  rm "$(ckpt "$out/other_rank" 0).prev"
  expect_error "rank-0-of-$ranks.bin holds the state of rank 1 of $ranks, not of rank 0" \
    run "$out/scene.toml" --quiet --out "$out/other_rank" --restart
else
  expect_error "holds no checkpoint" run "$out/scene.toml" --quiet --out "$out/missing" --restart
fi

# The frame file a restart continues.
/usr/bin/python3 "$break_h5" "$out/whole/frames.h5" "$out/broken" frames_no_velocity frames_time_nan
for case in frames_no_velocity frames_time_nan; do
  fresh "$case"
  cp "$out/broken/$case.h5" "$out/$case/frames.h5"
  regex="no dataset /frames/000000/velocity"
  [ "$case" = frames_time_nan ] && regex="frames.h5:/frames/000000: attribute time is not finite"
  expect_error "$regex" run "$out/scene.toml" --quiet --out "$out/$case" --restart
done
echo "PASS: broken partition files, checkpoints and frame files refused cleanly on $ranks rank(s)"
