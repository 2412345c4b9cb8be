#!/usr/bin/env bash
# Installs, on top of scripts/setup.sh, what the benchmarks and `prism compare` reports
# use: the peer renderers (Blender's Cycles, POV-Ray 3.7), Python with NumPy and
# OpenImageIO for the scripts, and Chromium to check the HTML report. Idempotent. CI does
# not need these; the test suite does not depend on them.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
PACKAGES=(blender povray python3-numpy python3-openimageio chromium)
missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
if ((${#missing[@]})); then
  echo "setup-bench: installing ${missing[*]}"
  SUDO=""
  if [[ $(id -u) -ne 0 ]]; then SUDO="sudo"; fi
  $SUDO apt-get update -q
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
else
  echo "setup-bench: all ${#PACKAGES[@]} packages present"
fi
