#!/usr/bin/env bash
# Configures and builds descent (Release) into build/. The CUDA backend is
# built when CMake finds a CUDA compiler (CUDACXX or nvcc on PATH; see
# scripts/common.sh); DESCENT_CUDA_ARCHITECTURES overrides the default
# architectures (75;80;90), e.g. DESCENT_CUDA_ARCHITECTURES=90.
set -euo pipefail
cd "$(dirname "$0")/.."
cuda_args=()
[ -z "${DESCENT_CUDA_ARCHITECTURES:-}" ] || cuda_args+=(-DCMAKE_CUDA_ARCHITECTURES="$DESCENT_CUDA_ARCHITECTURES")
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release "${cuda_args[@]}"
cmake --build build -j"$(nproc)"
