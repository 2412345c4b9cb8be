#!/usr/bin/env bash
# Configures and builds Prism into build/ (Release), after installing what is missing.
# Extra arguments go to CMake's configure step, e.g. -DPRISM_SANITIZE=ON.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
BUILD_DIR=${PRISM_BUILD_DIR:-build}
cmake -S . -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=${PRISM_BUILD_TYPE:-Release} "$@"
cmake --build "$BUILD_DIR" --parallel "$(nproc)"
