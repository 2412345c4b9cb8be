#!/usr/bin/env bash
# Reframing from the command line: --camera auto frames the scene's bounds as the default
# camera does, even when the file has cameras; --look-from/--look-at/--up/--fov move the camera
# chosen, and the EXR records where it stood. Bad vectors are refused in one line.
# Usage: camera.sh PRISM SOURCE_DIR
source "$(dirname "$0")/lib/common.bash" "$@"

SCENE="$SRC/scenes/spheres.gltf"  # its own camera, 'main'
BOX=/usr/share/assimp/models/glTF2/BoxTextured-glTF/BoxTextured.gltf  # no camera
attr() { iinfo -v "$1" | sed -n "s/^ *prism:$2: \"\(.*\)\"$/\1/p"; }

"$PRISM" render "$BOX" -o "$TMP/default.exr" --res 32x24 -q 2>/dev/null || fail "default camera render"
"$PRISM" render "$BOX" -o "$TMP/auto.exr" --res 32x24 --camera auto -q 2>/dev/null || fail "auto render"
[[ "$(attr "$TMP/default.exr" camera)" == default ]] || fail "default camera named $(attr "$TMP/default.exr" camera)"
[[ "$(attr "$TMP/auto.exr" camera)" == auto ]] || fail "auto camera named $(attr "$TMP/auto.exr" camera)"
default_at=$(attr "$TMP/default.exr" cameraPosition)
[[ -n "$default_at" && "$(attr "$TMP/auto.exr" cameraPosition)" == "$default_at" ]] ||
  fail "--camera auto stands at $(attr "$TMP/auto.exr" cameraPosition), the default camera at $default_at"
cmp -s <(oiiotool "$TMP/default.exr" --printstats 2>&1 | grep -v File) \
  <(oiiotool "$TMP/auto.exr" --printstats 2>&1 | grep -v File) || fail "--camera auto renders another image than the default camera"

# A file with a camera: auto stands elsewhere, at the framing position.
"$PRISM" render "$SCENE" -o "$TMP/main.exr" --res 32x24 -q || fail "main render"
"$PRISM" render "$SCENE" -o "$TMP/framed.exr" --res 32x24 --camera auto -q || fail "auto render of a file with cameras"
[[ "$(attr "$TMP/main.exr" camera)" == main ]] || fail "file camera named $(attr "$TMP/main.exr" camera)"
[[ "$(attr "$TMP/framed.exr" camera)" == auto ]] || fail "--camera auto with file cameras named $(attr "$TMP/framed.exr" camera)"
[[ "$(attr "$TMP/framed.exr" cameraPosition)" != "$(attr "$TMP/main.exr" cameraPosition)" ]] ||
  fail "--camera auto stands where the file's camera does"

# Moved: the position lands in the metadata as given; world-to-camera takes the look-at point
# onto the camera's -Z axis (x = y = 0).
"$PRISM" render "$SCENE" -o "$TMP/moved.exr" --res 32x24 --look-from 1,2,30 --look-at 0,0.5,0 --fov 30 -q || fail "moved render"
[[ "$(attr "$TMP/moved.exr" cameraPosition)" == "1,2,30" ]] || fail "moved camera at $(attr "$TMP/moved.exr" cameraPosition)"
[[ "$(attr "$TMP/moved.exr" camera)" == "main (moved)" ]] || fail "moved camera named $(attr "$TMP/moved.exr" camera)"
python3 - "$(iinfo -v "$TMP/moved.exr" | sed -n 's/^ *worldToCamera: //p')" <<'PY' || fail "worldToCamera does not look at 0,0.5,0"
import sys
m = [float(v) for v in sys.argv[1].split(",")]
p = (0.0, 0.5, 0.0, 1.0)  # row vector times the matrix, as OpenEXR stores it
c = [sum(p[r] * m[r * 4 + k] for r in range(4)) for k in range(4)]
dist = (1 ** 2 + 1.5 ** 2 + 30 ** 2) ** 0.5
ok = abs(c[0]) < 1e-4 and abs(c[1]) < 1e-4 and abs(c[2] + dist) < 1e-3
print(c, dist)
sys.exit(0 if ok else 1)
PY
# --look-from alone keeps the direction of view; the image differs from the file camera's.
"$PRISM" render "$SCENE" -o "$TMP/shifted.exr" --res 32x24 --look-from 0,1,12 -q || fail "--look-from alone"
[[ "$(attr "$TMP/shifted.exr" cameraPosition)" == "0,1,12" ]] || fail "--look-from alone: at $(attr "$TMP/shifted.exr" cameraPosition)"

# A job file takes the same, as keys.
cat >"$TMP/jobs.json" <<JOBS
{"version": 1, "jobs": [
  {"name": "auto", "scene": "$SCENE", "camera": "auto", "res": "32x24", "output": "$TMP/job-auto.exr"},
  {"name": "moved", "scene": "$SCENE", "look-from": "1,2,30", "res": "32x24", "output": "$TMP/job-moved.exr"}]}
JOBS
"$PRISM" batch "$TMP/jobs.json" -q || fail "batch with camera keys exited $?"
[[ "$(attr "$TMP/job-auto.exr" cameraPosition)" == "$(attr "$TMP/framed.exr" cameraPosition)" ]] || fail "batch camera auto at $(attr "$TMP/job-auto.exr" cameraPosition)"
[[ "$(attr "$TMP/job-moved.exr" cameraPosition)" == "1,2,30" ]] || fail "batch look-from at $(attr "$TMP/job-moved.exr" cameraPosition)"

expect 2 "^prism: error: --look-from 1,2: expected X,Y,Z, three finite numbers$" -- render "$SCENE" -o "$TMP/bad.exr" --look-from 1,2
expect 2 "^prism: error: --look-at 1,2,nan: expected X,Y,Z, three finite numbers$" -- render "$SCENE" -o "$TMP/bad.exr" --look-at 1,2,nan
expect 2 "^prism: error: --up 0,1,0,1: expected X,Y,Z, three finite numbers$" -- render "$SCENE" -o "$TMP/bad.exr" --up 0,1,0,1
expect 2 "^prism: error: --fov 180: must be above 0 and below 180 degrees$" -- render "$SCENE" -o "$TMP/bad.exr" --fov 180
expect 2 "^prism: error: --look-at 1,1,1: is where the camera stands; look at another point$" -- render "$SCENE" -o "$TMP/bad.exr" --look-from 1,1,1 --look-at 1,1,1
expect 2 "^prism: error: --up 0,0,0: has no direction$" -- render "$SCENE" -o "$TMP/bad.exr" --look-at 0,0,0 --up 0,0,0
expect 2 "^prism: error: --up 0,1,0: is along the direction of view; give another --up$" -- render "$SCENE" -o "$TMP/bad.exr" --look-from 0,9,0 --look-at 0,0,0
[[ -e "$TMP/bad.exr" ]] && fail "a refused camera wrote its output"

echo "$failures failed"
[[ $failures -eq 0 ]]
