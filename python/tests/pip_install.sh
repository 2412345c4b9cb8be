#!/usr/bin/env bash
# `pip install .` from a fresh copy of the sources, in a virtual environment with no access
# to any package index, then the module imported from outside the tree renders a scene.
# Arguments: PYTHON SOURCE_DIR BUILD_DIR (a configured build folder to reuse, so only the
# module is linked again).
set -euo pipefail
python=$1 source=$2 build=$3
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$python" -m venv --system-site-packages "$work/venv"
PRISM_BUILD_DIR=$build PIP_NO_INDEX=1 "$work/venv/bin/pip" install --no-deps -q "$source"
cd "$work"
"$work/venv/bin/python" - "$source" <<'PY'
import pathlib, sys
import prism
root = pathlib.Path(sys.argv[1])
location = pathlib.Path(prism.__file__).resolve()
assert "venv" in location.parts, f"imported {location}, not the installed copy"
render = prism.Session(str(root / "scenes" / "spheres.gltf")).render(resolution=(16, 12))
assert render.image.shape == (12, 16, 4) and render.image[..., :3].max() > 0
print(f"ok: installed prism {prism.__version__} at {location.parent} renders")
PY
