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
PYTHON=/usr/bin/python3  # Debian's, with matplotlib
helix=(jobs/helix.toml --set "mesh.helix.preset=\"${PRESET}\"")
machine() {  # the machine beside every figure
  {
    echo "date: $(date -u +%Y-%m-%dT%H:%MZ)"
    echo "cpu: $(lscpu | sed -n 's/^Model name:[[:space:]]*//p'), $(nproc --all) cores"
    echo "load average at start: $(cut -d" " -f1-3 /proc/loadavg) (a shared machine: wall times include other jobs)"
    echo "command: $*"
  }
}
