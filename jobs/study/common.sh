# Shared settings of the study jobs (sourced). DESCENT: the binary
# (default build/src/app/descent); PRESET: helix size (default 82k);
# RESULTS: where results go (default bench/results/study); MPIEXEC: launcher.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
cd "$root"
DESCENT=${DESCENT:-build/src/app/descent}
PRESET=${PRESET:-82k}
RESULTS=${RESULTS:-bench/results/study}
MPIEXEC=${MPIEXEC:-mpiexec --oversubscribe}
export OMP_NUM_THREADS=${OMP_NUM_THREADS:-1}
# Open MPI refuses to run as root unless told (containers, CI).
if [ "$(id -u)" = 0 ]; then export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1; fi
PYTHON=/usr/bin/python3  # Debian's, with matplotlib
# Jacobi's D^-1, the papers' preconditioner and the default until issue 25
# made the automatic Chebyshev's the multilevel one: the studies of the
# papers' methods and of issue 11's parameters pin it (after the scene).
JACOBI=(--set 'solver.preconditioner="jacobi"')
# The paper's budget: 96 iterations a step, no accuracy target (the main
# job, jobs/helix.toml, runs each step to 1e-2).
helix=(jobs/helix.toml --set "mesh.helix.preset=\"${PRESET}\"" --set solver.accuracy=0
       --set solver.iterations=96 "${JACOBI[@]}")
# Newton's eps*, the truth, with its direct solver: exact as CG to 1e-10,
# and about 20x faster on these meshes.
TRUTH=(--set 'solver.newton_solver="ldlt"')
# Chebyshev as it ran before issue 11: the paper's fixed parameters.
FIXED="method=chebyshev chebyshev_parameters=fixed rho=0.96 chebyshev_delay=10 alpha_max=1"
# Case keys of a `descent tune` output file: phase_rho, phase_lengths, alpha_max.
tuned_keys() {
  local f=$1
  echo "method=chebyshev chebyshev_parameters=fixed" \
    "phase_rho=$(sed -n 's/^phase_rho = //p' "$f" | tr -d ' ')" \
    "phase_lengths=$(sed -n 's/^phase_lengths = //p' "$f" | tr -d ' ')" \
    "alpha_max=$(sed -n 's/^alpha_max = //p' "$f" | tr -d ' ')"
}
machine() {  # the machine beside every figure
  {
    echo "date: $(date -u +%Y-%m-%dT%H:%MZ)"
    echo "cpu: $(lscpu | sed -n 's/^Model name:[[:space:]]*//p'), $(nproc --all) cores"
    echo "load average at start: $(cut -d" " -f1-3 /proc/loadavg) (a shared machine: wall times include other jobs)"
    echo "command: $*"
  }
}
# Runs a `descent study` command with --study-out OUT, recording the machine
# and its progress in OUT, and keeps of its study.csv only the last record of
# each case and frame (ends.csv: the step's e, iterations and ms); the full
# traces (tens of MB for long cases) are the command's to regenerate.
#   study_ends OUT descent-study-command...
study_ends() {
  local out=$1
  shift
  mkdir -p "$out"
  machine "$*" > "$out/machine.txt"
  "$@" > "$out/progress.log"
  awk -F, 'NR == 1 { print; next }
           { key = $2 "," $3; if (key != prev && last != "") print last; prev = key; last = $0 }
           END { print last }' "$out/study.csv" > "$out/ends.csv"
  rm "$out/study.csv"
}
