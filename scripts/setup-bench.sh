#!/usr/bin/env bash
# Installs, on top of what scripts/setup.sh installs, what the benchmarks use: the peer
# renderers (Blender's Cycles, POV-Ray 3.7), Python with NumPy and OpenImageIO for the
# scripts in bench/, and GNU time for the macro benchmark's peak memory (bench/macro.py).
# Idempotent. CI and the test suite do not need these.
set -euo pipefail
cd "$(dirname "$0")/.."
exec bash scripts/setup.sh blender povray python3-numpy python3-openimageio time
