#!/usr/bin/env bash
# Installs dependencies, builds, and runs every test through ctest and the
# Slurm job test; then the whole suite again in a build with AddressSanitizer
# and UndefinedBehaviorSanitizer and without PETSc (DESCENT_SANITIZE=0 skips
# that second pass; it leaves out the tests labelled `long`).
set -euo pipefail
source "$(dirname "$0")/common.sh"
ctest --test-dir build --output-on-failure -j"$(nproc)"
# The Slurm job scripts under a one-node Slurm it starts (skips without root).
bash tests/slurm/slurm_job_test.sh build

if [ "${DESCENT_SANITIZE:-1}" != "0" ]; then
  echo "== the suite again under ASan + UBSan (build-sanitize/)"
  # CUDA off: the sanitizers watch host code, and CI time is better spent
  # than compiling the device kernels twice. PETSc off: this pass is also
  # the build without the optional PETSc, where its methods must refuse by
  # name and everything else must pass.
  cmake -S . -B build-sanitize -DCMAKE_BUILD_TYPE=Debug -DDESCENT_ENABLE_CUDA=OFF \
    -DDESCENT_ENABLE_PETSC=OFF \
    -DCMAKE_CXX_FLAGS="-O1 -fno-omit-frame-pointer -fsanitize=address,undefined -fno-sanitize-recover=all" \
    -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined"
  cmake --build build-sanitize -j"$(nproc)"
  # Open MPI's own allocations are still live at exit: leak reports would be
  # about the library, not descent.
  # Tests labelled `long` (tests/CMakeLists.txt) repeat paths the others take,
  # 5-10x slower here: left out so CI stays within its time.
  ASAN_OPTIONS=detect_leaks=0 UBSAN_OPTIONS=print_stacktrace=1 \
    ctest --test-dir build-sanitize --output-on-failure -j"$(nproc)" -LE long
fi
