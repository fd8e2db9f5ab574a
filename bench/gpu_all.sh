#!/usr/bin/env bash
# Every check of the CUDA backend that needs a GPU, in one command, on a
# machine with a CUDA device (docs/gpu.md):
#
#   bash bench/gpu_all.sh             # build, gpu tests, compute-sanitizer, benchmarks
#   bash bench/gpu_all.sh build test  # any of: build test sanitize bench
#
# Builds for sm_90 (DESCENT_CUDA_ARCHITECTURES overrides) into build-gpu/
# (DESCENT_GPU_BUILD overrides); results into bench/results/ (DESCENT_GPU_RESULTS).
# Where MPI, METIS, HDF5, Eigen, GoogleTest, toml++ and CLI11 are missing
# (the lent GPU machines have only nvcc and CMake), it uses the bundle in
# .devicedeps/, made beforehand on a Debian machine with the project's
# packages, from the checkout root:
#   bash ../shared/tools/device-bundle.sh --extra libtomlplusplus-dev --extra libcli11-dev
# Results go to bench/results/gpu_checks.md (tests, sanitizer) and
# bench/results/gpu_table1.md (benchmarks), each with GPU, driver and date.
set -euo pipefail
cd "$(dirname "$0")/.."
steps=("$@")
[ ${#steps[@]} -gt 0 ] || steps=(build test sanitize bench)

if [ -f .devicedeps/env.sh ] && ! command -v mpicxx >/dev/null 2>&1; then
  # shellcheck disable=SC1091
  source .devicedeps/env.sh
fi
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMP_NUM_THREADS=1 GTEST_COLOR=no
if [ -z "${CUDACXX:-}" ]; then
  CUDACXX=$(command -v nvcc || echo /usr/local/cuda/bin/nvcc)
  export CUDACXX
fi
export PATH="$(dirname "$CUDACXX"):$PATH"
build=${DESCENT_GPU_BUILD:-build-gpu}
results=${DESCENT_GPU_RESULTS:-bench/results}
checks=$results/gpu_checks.md
mkdir -p "$results"

header() {
  echo "# $1"
  echo
  echo "- date: $(date -u '+%Y-%m-%d %H:%M UTC')"
  echo "- GPU: $(nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader 2>/dev/null || echo 'nvidia-smi not found')"
  echo "- commit: $(git rev-parse --short HEAD 2>/dev/null || echo unknown)$(git diff --quiet 2>/dev/null || echo ' (with local changes)')"
  echo
  echo '```'
  "$build/src/app/descent" --version
  echo '```'
  echo
}

for step in "${steps[@]}"; do
  case $step in
    build)
      cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DDESCENT_ENABLE_CUDA=ON \
        -DCMAKE_CUDA_COMPILER="$CUDACXX" \
        -DCMAKE_CUDA_ARCHITECTURES="${DESCENT_CUDA_ARCHITECTURES:-90}"
      cmake --build "$build" -j"$(nproc)" --target descent descent_kernel_bench \
        test_cuda_backend test_engine_assembly
      "$build/src/app/descent" --version
      ;;
    test)
      # The gpu label (CUDA vs CPU, ranks sharing the device, graphs, the
      # spectrum estimate) and the engine's assemblies on the host; the full
      # log beside the summary.
      log=$results/gpu_tests.log
      status=0
      ctest --test-dir "$build" -L gpu -E sanitizer -V >"$log" 2>&1 || status=1
      ctest --test-dir "$build" -R test_engine_assembly --output-on-failure >>"$log" 2>&1 || status=1
      {
        header "CUDA backend checks"
        echo '```'
        grep -E '^[0-9]+: \[ (gpu|scatter|engine)|Skipped|Passed|Failed|tests passed' "$log" | sed "s|$PWD/||g" || true
        echo '```'
      } | tee "$checks"
      [ $status = 0 ] || { echo "gpu_all: GPU tests failed; see $log" >&2; exit 1; }
      ;;
    sanitize)
      log=$results/gpu_sanitizer.log
      status=0
      ctest --test-dir "$build" -R gpu.sanitizer -V >"$log" 2>&1 || status=1
      {
        echo
        echo "## compute-sanitizer (memcheck, racecheck) on the small helix"
        echo
        echo '```'
        grep -E 'ERROR SUMMARY|skipped:|Skipped|Passed|Failed|tests passed' "$log" || true
        echo '```'
      } | tee -a "$checks"
      [ $status = 0 ] || { echo "gpu_all: compute-sanitizer found errors; see $log" >&2; exit 1; }
      ;;
    bench)
      python3 bench/gpu_table1.py --build "$build" --output "$results/gpu_table1.md"
      ;;
    *)
      echo "gpu_all: unknown step '$step' (build, test, sanitize, bench)" >&2
      exit 2
      ;;
  esac
done
echo "gpu_all: done (${steps[*]}); see $checks and $results/gpu_table1.md"
