#!/usr/bin/env bash
# prism info --json: the schema of docs/info.md with the file's real values, and triangle
# counts that agree between the meshes and the timing (built + dropped = as placed).
# Usage: info_json.sh PRISM SOURCE_DIR
source "$(dirname "$0")/lib/common.bash" "$@"

M=/usr/share/assimp/models/glTF2
"$PRISM" info --json --timing "$SRC/scenes/spheres.gltf" >"$TMP/spheres.json" || fail "info --json exited $?"
python3 - "$TMP/spheres.json" <<'PY' || fail "spheres.gltf's JSON (above)"
import json, sys
j = json.load(open(sys.argv[1]))
bad = []
def check(what, ok):
    if not ok: bad.append(what)
check("version 1", j["version"] == 1)
check("bounds", j["bounds"]["min"][0] == -6.0 and j["bounds"]["max"] == [6.0, 6.0, 5.0])
cam = j["cameras"]
check("one camera 'main' at 0,2,7", len(cam) == 1 and cam[0]["name"] == "main" and cam[0]["position"] == [0.0, 2.0, 7.0])
check("camera perspective", cam[0]["projection"] == "perspective" and 37 < cam[0]["yfov_degrees"] < 38)
check("meshes", j["meshes"]["count"] == 2 and j["meshes"]["triangles_as_placed"] == 4)
check("materials", len(j["materials"]) == 6 and j["materials"][3]["name"] == "glass" and j["materials"][3]["transmission"] == 1.0)
check("lights", len(j["lights"]) >= 1 and all(l["unit"] in ("cd", "lx") for l in j["lights"]))
check("spheres", j["spheres"] >= 1)
check("no animation", j["animations"] == 0 and j["morph_targets"] == 0)
check("extensions", "PRISM_sphere" in j["extensions"]["used"])
check("features", j["features"]["spheres"] == "analytic" and "shadows=yes" in j["features"]["set"])
t = j["timing"]
check("triangles agree", t["triangles_built"] + t["triangles_degenerate"] + t["triangles_nonfinite"] == j["meshes"]["triangles_as_placed"])
for b in bad: print("FAIL:", b)
sys.exit(1 if bad else 0)
PY

# Animations, morph targets and skins are counted from the file.
"$PRISM" info --json "$M/glTF-Sample-Models/AnimatedMorphCube-glTF/AnimatedMorphCube.gltf" >"$TMP/morph.json" 2>/dev/null || fail "info --json AnimatedMorphCube"
python3 -c "import json,sys; j=json.load(open(sys.argv[1])); sys.exit(0 if j['animations']==1 and j['morph_targets']==2 else 1)" "$TMP/morph.json" ||
  fail "AnimatedMorphCube: animations/morph targets $(python3 -c "import json,sys; j=json.load(open(sys.argv[1])); print(j['animations'], j['morph_targets'])" "$TMP/morph.json")"
"$PRISM" info --json "$M/simple_skin/simple_skin.gltf" >"$TMP/skin.json" 2>/dev/null || fail "info --json simple_skin"
python3 -c "import json,sys; j=json.load(open(sys.argv[1])); sys.exit(0 if j['animations']==1 and j['skins']==1 else 1)" "$TMP/skin.json" ||
  fail "simple_skin: animations/skins $(python3 -c "import json,sys; j=json.load(open(sys.argv[1])); print(j['animations'], j['skins'])" "$TMP/skin.json")"

# On every assimp glTF file that loads: built + dropped = as placed, in the text as in JSON.
checked=0
while IFS= read -r -d '' f; do
  "$PRISM" info --json --timing "$f" >"$TMP/f.json" 2>/dev/null || continue
  python3 - "$TMP/f.json" <<'PY' || fail "$f: triangle counts disagree"
import json, sys
j = json.load(open(sys.argv[1])); t = j["timing"]
sys.exit(0 if t["triangles_built"] + t["triangles_degenerate"] + t["triangles_nonfinite"] == j["meshes"]["triangles_as_placed"] else 1)
PY
  checked=$((checked + 1))
done < <(find "$M" \( -name '*.gltf' -o -name '*.glb' \) -print0)
echo "triangle counts agree on $checked files"
[[ $checked -gt 5 ]] || fail "only $checked files loaded"
"$PRISM" info --timing "$SRC/scenes/spheres.gltf" | grep -q "^timing: .*; 4 triangles built (0 degenerate and 0 non-finite dropped)" ||
  fail "timing line: $("$PRISM" info --timing "$SRC/scenes/spheres.gltf" | grep timing)"

echo "$failures failed"
[[ $failures -eq 0 ]]
