#!/usr/bin/env bash
# Installs dependencies, builds, and runs every test through ctest.
set -euo pipefail
source "$(dirname "$0")/common.sh"
ctest --test-dir build --output-on-failure -j"$(nproc)"
