#!/usr/bin/env bash
# --restart continues only the run its checkpoint came from: a changed
# material, a changed mesh (same counts, other coordinates) and another
# rank count are refused with exit 1 and a message naming what differs; a
# larger time.frames continues.
#   restart_checks.sh DESCENT OUT_DIR RANKS
set -euo pipefail
descent=$1 out=$2 ranks=$3
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMP_NUM_THREADS=1
rm -rf "$out" && mkdir -p "$out"
fail() { echo "FAIL: $*"; exit 1; }
run() { mpiexec -n "$1" --oversubscribe "$descent" run "$out/scene.toml" --quiet --out "$out/run" "${@:2}"; }
# expect_refusal RANKS REGEX [options...]: exit 1 and REGEX on stderr.
expect_refusal() {
  local np=$1 regex=$2 code=0
  shift 2
  run "$np" --restart "$@" 2>"$out/err" || code=$?
  cat "$out/err"
  [ "$code" = 1 ] || fail "exit $code, not 1, for --restart $*"
  grep -qE "$regex" "$out/err" || fail "the refusal does not match '$regex'"
}
box_mesh() {  # box_mesh SIZE: a 2x2x2-cell box of edge SIZE as a MEDIT file
  printf '[mesh]\ngenerator = "box"\n[mesh.box]\ncells = [2, 2, 2]\nsize = [%s, %s, %s]\n' \
    "$1" "$1" "$1" >"$out/box.toml"
  "$descent" mesh "$out/box.toml" -o "$out/box.mesh" >/dev/null
}
box_mesh 1.0
cat >"$out/scene.toml" <<TOML
gravity = [0.0, -9.81, 0.0]
[mesh]
file = "$out/box.mesh"
[[fixed]]
box_min = [-1.0, 0.9, -1.0]
box_max = [2.0, 2.0, 2.0]
[time]
frames = 4
[solver]
iterations = 16
[output]
checkpoint_every = 2
TOML
run "$ranks"
expect_refusal "$ranks" "material.young is 250000 now but was 1e\\+05" --set material.young=2.5e5
other=$((ranks == 1 ? 2 : 1))
expect_refusal "$other" "checkpoints of a run on $ranks rank\(s\), not $other" --set time.frames=6
expect_refusal "$ranks" "precision is \"float\" now but was \"double\"" --precision float
box_mesh 1.5  # the same counts and ids, other coordinates
expect_refusal "$ranks" "the mesh differs \\(mesh.digest.* is [0-9]+ now but was [0-9]+" --set time.frames=6
box_mesh 1.0
run "$ranks" --restart --set time.frames=6
[ "$(cut -d, -f1 "$out/run/stats.csv" | tail -n +2 | tr '\n' ' ')" = "1 2 3 4 5 6 " ] ||
  fail "the continued run does not list frames 1-6 once"
echo "PASS: restarts refused for what differs, continued for more frames, on $ranks rank(s)"
