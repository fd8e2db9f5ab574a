# Sourced by the entry scripts: install what is missing, build, and set the
# environment every MPI run here needs.
cd "$(dirname "${BASH_SOURCE[0]}")/.."
bash scripts/install-deps.sh
# The CUDA toolkit installs nvcc outside PATH: point CMake at it, so the CUDA
# backend is compiled wherever the toolkit is (CI included).
if [ -z "${CUDACXX:-}" ] && ! command -v nvcc >/dev/null 2>&1 && [ -x /usr/local/cuda/bin/nvcc ]; then
  export CUDACXX=/usr/local/cuda/bin/nvcc
  export PATH="/usr/local/cuda/bin:$PATH"
fi
bash scripts/build.sh
# Open MPI refuses to run as root unless told; CI and containers run as root.
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
# One OpenMP thread per rank unless asked: ranks already fill the cores.
export OMP_NUM_THREADS=${OMP_NUM_THREADS:-1}
