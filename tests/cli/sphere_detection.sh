#!/usr/bin/env bash
# Sphere-shaped meshes from the command line (docs/spheres.md): `prism info` lists them,
# `prism render --detect-spheres` replaces them and says so, --sphere-tolerance is checked.
# Usage: sphere_detection.sh PRISM SOURCE_DIR
source "$(dirname "$0")/lib/common.bash" "$@"
SCENE="$TMP/ball.gltf"

# A latitude/longitude sphere mesh 'Ball' (radius 0.5 at (0, 0.5, 0), 32 x 16, seam and
# pole vertices repeated as exporters write them) on a floor quad, with a light and a camera.
python3 - "$SCENE" <<'EOF'
import base64, json, math, struct, sys
seg, rings, r, c = 32, 16, 0.5, (0.0, 0.5, 0.0)
pos, idx = [], []
for i in range(rings + 1):
    t = math.pi * i / rings
    for j in range(seg + 1):
        p = 2 * math.pi * (j % seg) / seg
        pos.append((c[0] + r * math.sin(t) * math.cos(p), c[1] + r * math.cos(t),
                    c[2] - r * math.sin(t) * math.sin(p)))
at = lambda i, j: i * (seg + 1) + j
for i in range(rings):
    for j in range(seg):
        idx += [at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j), at(i + 1, j + 1), at(i, j + 1)]
floor = [(-3, 0, 3), (3, 0, 3), (3, 0, -3), (-3, 0, -3)]
floor_idx = [0, 1, 2, 0, 2, 3]
blob = b"".join(struct.pack("<3f", *v) for v in pos) + struct.pack("<%dI" % len(idx), *idx)
blob += b"".join(struct.pack("<3f", *v) for v in floor) + struct.pack("<6I", *floor_idx)
o1 = 12 * len(pos); o2 = o1 + 4 * len(idx); o3 = o2 + 48
def acc(view, count, kind, ctype, lo=None, hi=None):
    a = {"bufferView": view, "count": count, "type": kind, "componentType": ctype}
    if lo: a.update(min=lo, max=hi)
    return a
gltf = {
  "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0, 1, 2, 3]}],
  "nodes": [{"name": "FloorNode", "mesh": 0}, {"name": "BallNode", "mesh": 1},
            {"name": "Lamp", "translation": [1, 3, 2],
             "extensions": {"KHR_lights_punctual": {"light": 0}}},
            {"name": "Cam", "camera": 0, "translation": [0, 1, 4]}],
  "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.01}}],
  "extensionsUsed": ["KHR_lights_punctual"],
  "extensions": {"KHR_lights_punctual": {"lights": [{"type": "point", "intensity": 20}]}},
  "materials": [{"name": "grey", "pbrMetallicRoughness": {"metallicFactor": 0}},
                {"name": "red", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.1, 0.1, 1],
                                                         "metallicFactor": 0}}],
  "meshes": [{"name": "Floor", "primitives": [{"attributes": {"POSITION": 2}, "indices": 3, "material": 0}]},
             {"name": "Ball", "primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 1}]}],
  "buffers": [{"byteLength": len(blob),
               "uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode()}],
  "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": o1},
                  {"buffer": 0, "byteOffset": o1, "byteLength": o2 - o1},
                  {"buffer": 0, "byteOffset": o2, "byteLength": 48},
                  {"buffer": 0, "byteOffset": o3, "byteLength": 24}],
  "accessors": [acc(0, len(pos), "VEC3", 5126, [min(v[k] for v in pos) for k in range(3)],
                    [max(v[k] for v in pos) for k in range(3)]),
                acc(1, len(idx), "SCALAR", 5125),
                acc(2, 4, "VEC3", 5126, [-3, 0, -3], [3, 0, 3]),
                acc(3, 6, "SCALAR", 5125)],
}
json.dump(gltf, open(sys.argv[1], "w"))
EOF

# prism info looks for sphere-shaped meshes only when asked: the weld costs more than the load.
"$PRISM" info "$SCENE" >"$TMP/info" 2>&1 || fail "info exited $?: $(cat "$TMP/info")"
grep -qx "sphere-shaped meshes: not looked for (--detect-spheres lists them)" "$TMP/info" &&
  echo "ok: info without --detect-spheres does not look" ||
  fail "info without --detect-spheres: $(grep sphere-shaped "$TMP/info")"
"$PRISM" info "$SCENE" --detect-spheres >"$TMP/info" 2>&1 || fail "info --detect-spheres exited $?: $(cat "$TMP/info")"
# Centre (0, 0.5, 0) to 1e-6 (x and z print as float rounding, e.g. 6.7e-18), radius 0.5.
line=$(grep -E "mesh \[1\] 'Ball' \(node 'BallNode'\): centre \(" "$TMP/info")
if grep -q "sphere-shaped meshes (tolerance 0.001): 1" "$TMP/info" &&
  echo "$line" | awk -F'[(), ]+' '{
    for (i = 1; i <= NF; ++i) if ($i == "centre") { x = $(i + 1); y = $(i + 2); z = $(i + 3) }
    for (i = 1; i <= NF; ++i) if ($i == "radius") r = $(i + 1)
    d = (x < 0 ? -x : x) + (y - 0.5 < 0 ? 0.5 - y : y - 0.5) + (z < 0 ? -z : z) + (r - 0.5 < 0 ? 0.5 - r : r - 0.5)
    exit !(d < 1e-6) }'; then
  echo "ok: info lists the ball"
else
  fail "info does not list the ball: $(grep -A2 sphere-shaped "$TMP/info")"
fi

"$PRISM" render "$SCENE" -o "$TMP/mesh.exr" --res 64x48 --integrator shadow -v --quiet \
  >"$TMP/out" 2>"$TMP/err" || fail "plain render exited $?"
grep -q "0 spheres" "$TMP/err" && ! grep -q "detect-spheres" "$TMP/err" &&
  echo "ok: without --detect-spheres the ball stays a mesh" ||
  fail "plain render: $(cat "$TMP/err")"

"$PRISM" render "$SCENE" -o "$TMP/sphere.exr" --res 64x48 --integrator shadow -v --quiet \
  --detect-spheres >"$TMP/out" 2>"$TMP/err" || fail "--detect-spheres render exited $?"
if grep -q "replaced mesh \[1\] 'Ball' (node 'BallNode')" "$TMP/err" &&
  grep -q "1 mesh replaced" "$TMP/err" && grep -q "1 spheres" "$TMP/err" &&
  [[ -s "$TMP/sphere.exr" ]]; then
  echo "ok: --detect-spheres replaced the ball and said so"
else
  fail "--detect-spheres: $(cat "$TMP/err")"
fi

# The same ball, drawn as a 32 x 16 mesh and as the exact sphere: close, not identical.
"$PRISM" diff "$TMP/mesh.exr" "$TMP/sphere.exr" --metric relmse --fail-above 0.01 >"$TMP/diff" 2>&1 &&
  echo "ok: mesh and analytic renders agree: $(cat "$TMP/diff")" ||
  fail "mesh and analytic renders differ: $(cat "$TMP/diff")"

# Far tighter than float positions can hold: nothing found, nothing replaced.
"$PRISM" render "$SCENE" -o "$TMP/tight.exr" --res 16x12 --quiet --detect-spheres \
  --sphere-tolerance 1e-12 >"$TMP/out" 2>"$TMP/err" || fail "tight tolerance exited $?"
grep -q "0 meshes replaced" "$TMP/err" && echo "ok: --sphere-tolerance 1e-12 finds none" ||
  fail "--sphere-tolerance 1e-12: $(cat "$TMP/err")"

for bad in 0 -1 nan 0.5; do
  rm -f "$TMP/bad.exr"
  "$PRISM" render "$SCENE" -o "$TMP/bad.exr" --detect-spheres --sphere-tolerance "$bad" \
    >"$TMP/out" 2>"$TMP/err"
  got=$?
  if [[ $got -eq 2 && $(wc -l <"$TMP/err") -eq 1 && ! -e "$TMP/bad.exr" ]] &&
    grep -q -- "--sphere-tolerance" "$TMP/err"; then
    echo "ok: --sphere-tolerance $bad -> $(cat "$TMP/err")"
  else
    fail "--sphere-tolerance $bad exited $got: $(cat "$TMP/err")"
  fi
done

echo "$failures failed"
[[ $failures -eq 0 ]]
