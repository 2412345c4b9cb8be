#!/usr/bin/env bash
# The README's first command: installs what is missing, builds, and renders the shipped
# default scene to out/spheres.exr with a PNG preview.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
mkdir -p out
BUILD_DIR=${PRISM_BUILD_DIR:-build}
"$BUILD_DIR/apps/prism" render scenes/spheres.gltf -o out/spheres.exr --preview out/spheres.png \
  --integrator whitted --spp 4 --background 0.2 "$@"
echo "EXR:     $(pwd)/out/spheres.exr"
echo "preview: $(pwd)/out/spheres.png"
