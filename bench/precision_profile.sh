#!/usr/bin/env bash
# Where float's time goes against double's on the CPU (issue 22, part 3:
# float at least 1.6x double, or the reason): `perf record` of the same run
# in each precision, one rank, one thread, then the samples grouped by the
# part of the iteration their function belongs to. Absolute samples are
# comparable between the two runs (same sampling rate); their ratio is
# each part's float speed-up.
#
#   bench/precision_profile.sh [BUILD_DIR]     # appends to bench/results/precision/profile.log
#   FRAMES=6 ITERATIONS=96 PRESET=82k bench/precision_profile.sh
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build}
frames=${FRAMES:-6}
iterations=${ITERATIONS:-96}
preset=${PRESET:-82k}
scratch=$(mktemp -d -t precision_profile.XXXXXX)
trap 'rm -rf "$scratch"' EXIT
command -v perf >/dev/null || { echo "perf is not installed (apt-get install linux-perf)"; exit 1; }
log=$root/bench/results/precision/profile.log
export OMP_NUM_THREADS=1
{
  echo "== $(date -u +%FT%TZ) $(lscpu | sed -n 's/^Model name: *//p'), $(nproc --all) cores; tree $(git -C "$root" rev-parse --short HEAD)"
  source_dir=$(sed -n 's/^CMAKE_HOME_DIRECTORY:INTERNAL=//p' "$build/CMakeCache.txt")
  echo "binary: ${build#"$root"/}/src/app/descent, built from $(git -C "$source_dir" log -1 --format=%h)"
  for precision in double float; do
    cmd=("$build/src/app/descent" run "$root/jobs/helix.toml" --set "mesh.helix.preset=\"$preset\""
         --set "time.frames=$frames" --set solver.accuracy=0 --set "solver.iterations=$iterations"
         --set 'solver.preconditioner="jacobi"' --precision "$precision" --out "$scratch/run"
         --overwrite)
    shown="${cmd[*]#"$root"/}"
    echo "command: perf record -o DATA ${shown//$scratch/SCRATCH}"
    perf record -q -o "$scratch/$precision.data" "${cmd[@]}" 2>&1 | grep "ns per tet-iteration"
    perf report -i "$scratch/$precision.data" --no-children --sort symbol --stdio 2>/dev/null |
      grep -E '^ +[0-9.]+%' >"$scratch/$precision.txt"
    echo "samples: $(perf report -i "$scratch/$precision.data" --stdio 2>/dev/null |
      sed -n 's/^# Samples: \([0-9.K]*\).*/\1/p' | head -1)"
  done
  python3 - "$scratch" <<'PY'
import re, sys
d = sys.argv[1]
# Parts of the iteration, by function name (first match wins).
parts = [
    ("energy checks (in double)", r"local_energy|element_energies_lanes|cube_root_scalar<double>|deformation_gradient<double>"),
    ("lanes: load corners and rest", r"load_lanes"),
    ("lanes: store corner results", r"store_lanes"),
    ("spectrum (Hessian products)", r"hessian_product|stress_derivative"),
    ("element math (lanes)", r"element_pass_lanes|Lanes<|descent::cube_root(\s|$)"),
    ("assembly gather", r"gather_corners"),
    ("vertex update", r"vertex_update"),
]
def load(precision):
    total, grouped = 0.0, {name: 0.0 for name, _ in parts}
    grouped["other"] = 0.0
    samples = None
    for line in open(f"{d}/{precision}.txt"):
        m = re.match(r"\s+([0-9.]+)%\s+\[.\]\s+(.*)", line) or re.match(r"\s+([0-9.]+)%\s+\S+\s+(.*)", line)
        if not m:
            continue
        share, name = float(m.group(1)), m.group(2)
        for part, pattern in parts:
            if re.search(pattern, name):
                grouped[part] += share
                break
        else:
            grouped["other"] += share
    return grouped
double, single = load("double"), load("float")
# The largest functions left in "other", for the record.
for precision in ("double", "float"):
    rest = []
    for line in open(f"{d}/{precision}.txt"):
        m = re.match(r"\s+([0-9.]+)%\s+\[.\]\s+(.*)", line) or re.match(r"\s+([0-9.]+)%\s+\S+\s+(.*)", line)
        if m and not any(re.search(p, m.group(2)) for _, p in parts):
            rest.append((float(m.group(1)), m.group(2)[:90]))
    print(f"{precision}, largest in other: " + "; ".join(f"{n} {v:.1f}%" for v, n in rest[:5]))
print("part | double % | float % ")
for part in list(double):
    print(f"{part} | {double[part]:.1f} | {single[part]:.1f}")
PY
} | tee -a "$log"
