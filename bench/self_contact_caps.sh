#!/usr/bin/env bash
# Self-contact on finely meshed bodies (docs/contact.md, "When pairs are
# found"): the shared bunny and dragon dropped with contact.self = true
# towards a tilted plane and a sphere, FRAMES frames on RANKS ranks, each
# RUNS times, this build and BASELINE's descent in turn: ms per frame and
# the contact report. Needs ../shared/meshes (skips without it).
#
#   BASELINE=/path/to/other/build bench/self_contact_caps.sh
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
meshes=${MESHES:-$root/../shared/meshes}
for f in bunny_ipc.msh dragon_16k.mesh; do
  [[ -f $meshes/$f ]] || { echo "self_contact_caps: $meshes/$f is absent; skipped" >&2; exit 0; }
done
runs=${RUNS:-2}
frames=${FRAMES:-2}
ranks=${RANKS:-2}
scratch=$(mktemp -d -t self_contact.XXXXXX)
trap 'rm -rf "$scratch"' EXIT
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMP_NUM_THREADS=1
cat >"$scratch/scene.toml" <<TOML
gravity = [0.0, -9.81, 0.0]
[material]
model = "corotated"
young = 2e5
poisson = 0.35
density = 1100
[[body]]
file = "$meshes/bunny_ipc.msh"
scale = 0.1
translate = [0.0, 0.5, 0.0]
velocity = [0.5, 0.0, 0.0]
[[body]]
file = "$meshes/dragon_16k.mesh"
scale = 0.3
rotate = { axis = [0, 0, 1], degrees = 30 }
translate = [0.0, 1.2, 0.0]
[body.material]
young = 1e6
[[obstacle]]
kind = "plane"
point = [0.0, 0.0, 0.0]
normal = [0.2, 1.0, 0.0]
friction = 0.3
[[obstacle]]
kind = "sphere"
centre = [0.6, 0.0, 0.0]
radius = 0.25
[contact]
self = true
friction = 0.2
[time]
dt = 0.02
frames = $frames
[output]
dir = "$scratch/out"
TOML
builds=("$root/build")
[[ -n ${BASELINE:-} ]] && builds+=("$BASELINE")
echo "# $(date -u '+%Y-%m-%d %H:%M') UTC, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs), $(nproc --all) cores, $ranks ranks, $frames frames"
for ((r = 1; r <= runs; ++r)); do
  for b in "${builds[@]}"; do
    name=$([[ $b == "$root/build" ]] && echo current || echo baseline)
    out=$(mpiexec -n "$ranks" --oversubscribe "$b/src/app/descent" run "$scratch/scene.toml" --overwrite 2>&1)
    echo "$name run $r: $(grep -oE '[0-9.]+ ms/frame' <<<"$out"); $(grep -oE 'contact between bodies [0-9.]+% of step time' <<<"$out"); $(grep -oE 'pair search [0-9.]+ ms, ghosts [0-9.]+ ms, terms [0-9.]+ ms, guard [0-9.]+ ms' <<<"$out")"
  done
done
