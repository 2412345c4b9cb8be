#!/usr/bin/env bash
# Installs, from Debian 12's archive, exactly the packages Prism builds, tests and
# renders with, plus any package names given as arguments (scripts/setup-bench.sh passes
# the benchmarks' own). Idempotent: packages already present are not touched, and apt is
# only called when something is missing.
set -euo pipefail

PACKAGES=(
  # toolchain
  g++ cmake pkg-config ninja-build
  # renderer dependencies
  libembree-dev libtbb-dev
  libopenimageio-dev openimageio-tools libopenexr-dev
  # glTF's PNG and JPEG images, decoded without OpenImageIO (scene_io/image_decoders.h)
  libpng-dev libturbojpeg0-dev
  libopencolorio-dev opencolorio-tools
  libtinygltf-dev nlohmann-json3-dev libstb-dev
  libcli11-dev
  # job fingerprints and checkpoint files (session/job_fingerprint.h): XXH3, stable across
  # machines
  libxxhash-dev
  # KHR_draco_mesh_compression: tinygltf is built without Draco, so scene_io decodes it
  libdraco-dev
  # tests and benchmarks
  libgtest-dev libgmock-dev libbenchmark-dev
  # real glTF files (good and broken) the tests load
  assimp-testmodels
  # `prism compare` labels its PNG plot with OpenImageIO's render_text, which needs a TTF
  # font; Debian ships none by default, and OIIO finds DejaVuSans here
  fonts-dejavu-core
  # tests/cli/compare.sh opens the HTML report in headless Chromium (large, but it is the
  # only way to check the page as a browser draws it)
  chromium
  # tests/cli/fuzz_smoke.sh builds the libFuzzer target over the glTF loader with clang's
  # -fsanitize=fuzzer,address,undefined (fuzz/build.sh); libFuzzer's runtime is in clang-rt
  clang libclang-rt-14-dev
  # tests/cli/hostile_confinement.sh checks with strace that a hostile file opens nothing
  # outside its folder
  strace
  # `mpirun -n R prism render` splits a frame over MPI ranks (distributed/); tests/cli/mpi.sh
  # checks it against a single process
  libopenmpi-dev openmpi-bin
  # tests/cli/slurm.sh runs docs/examples/prism-batch.sbatch on a single-node Slurm cluster
  slurm-wlm munge
  # the Python module (python/): pybind11 over the job API, NumPy arrays, pytest in CI, a
  # virtual environment to check `pip install .`, matplotlib for docs/python.md's example
  pybind11-dev python3-dev python3-numpy python3-pytest python3-venv python3-matplotlib
  "$@"
)

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}"
  SUDO=""
  if [[ $(id -u) -ne 0 ]]; then SUDO="sudo"; fi
  $SUDO apt-get update -q
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
else
  echo "setup: all ${#PACKAGES[@]} packages present"
fi
