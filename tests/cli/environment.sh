#!/usr/bin/env bash
# Environment maps on the command line and in job files: a map lights and backs the render,
# --hide-environment leaves the backdrop at alpha 0 and black, hostile maps are refused in
# one line naming the file (exit 2), and a batch job renders again when its map changes.
# Usage: environment.sh PRISM SOURCE_DIR
source "$(dirname "$0")/lib/common.bash" "$@"

SCENE="$SRC/scenes/spheres.gltf"
BOX=/usr/share/assimp/models/glTF2/BoxTextured-glTF/BoxTextured.gltf
cd "$TMP" || exit 1

# Any non-negative EXR is a map: a render of the shipped scene makes one.
"$PRISM" render "$SCENE" -o map.exr --res 64x32 --spp 1 --background 0.5 -q ||
  fail "could not render a map"
"$PRISM" render "$SCENE" -o big.exr --res 512x256 --spp 1 --background 0.5 -q ||
  fail "could not render a big map"

"$PRISM" render "$BOX" -o lit.exr --res 32x24 --spp 1 --environment map.exr \
  --environment-rotation 45 --environment-intensity 2 -q 2>err || fail "map render: $(cat err)"
"$PRISM" render "$BOX" -o hidden.exr --res 32x24 --spp 1 --environment map.exr \
  --hide-environment -q 2>err || fail "hidden render: $(cat err)"
# The top-left corner sees the sky: lit by the map where seen, black and transparent hidden.
corner() { oiiotool "$1" --cut 1x1+0+0 --printstats | awk '/Stats Min/ {print $3, $4, $5, $6}'; }
read -r r g b a <<<"$(corner lit.exr)"
awk "BEGIN {exit !($a == 0 && $r > 0)}" && echo "ok: the map is the backdrop ($r $g $b $a)" ||
  fail "lit corner $r $g $b $a"
read -r r g b a <<<"$(corner hidden.exr)"
awk "BEGIN {exit !($a == 0 && $r == 0 && $g == 0 && $b == 0)}" &&
  echo "ok: hidden backdrop is black" || fail "hidden corner $r $g $b $a"

echo "not an image" >notes.hdr
mkdir -p folder.exr
expect 2 "missing.exr: no such file" -- render "$SCENE" -o a.exr --environment missing.exr
expect 2 "notes.hdr: not an environment map" -- render "$SCENE" -o a.exr --environment notes.hdr
expect 2 "folder.exr: not a regular file" -- render "$SCENE" -o a.exr --environment folder.exr
expect 2 "big.exr: .*larger than Prism reads here" -- render "$SCENE" -o a.exr \
  --environment big.exr --memory-limit 0.001 --res 16x12
head -c 3000 big.exr >truncated.exr
expect 2 "truncated.exr" -- render "$SCENE" -o a.exr --environment truncated.exr
expect 2 "--environment-intensity" -- render "$SCENE" -o a.exr --environment map.exr \
  --environment-intensity -1
# A uniform colour: --background takes L or R,G,B.
"$PRISM" render "$BOX" -o colour.exr --res 16x12 --spp 1 --background 0.1,0.2,0.3 -q 2>err ||
  fail "--background R,G,B: $(cat err)"
read -r r g b a <<<"$(corner colour.exr)"
awk "BEGIN {exit !($r == 0.1 && $g == 0.2 && $b == 0.3 && $a == 0)}" &&
  echo "ok: a uniform colour backdrop" || fail "colour corner $r $g $b $a"
for bad in 1,2 0.5x -1 nan 1,2,3,4 ""; do
  expect 2 "--background" -- render "$SCENE" -o a.exr --background "$bad"
done
[[ -e a.exr ]] && fail "a refused render left a.exr behind"

# Batch: the key is the option's name, its path relative to the job file, and the map's
# contents are part of the fingerprint.
mkdir -p b
cp map.exr b/sky.exr
cat >b/jobs.json <<JSON
{"version": 1, "defaults": {"res": "16x12", "spp": 1},
 "jobs": [{"name": "env", "scene": "$SCENE", "output": "env.exr", "environment": "sky.exr",
           "environment-rotation": 90, "hide-environment": true}]}
JSON
status() { python3 -c "import json; print(json.load(open('b/batch-report.json'))['jobs'][0]['status'])"; }
"$PRISM" batch b/jobs.json --quiet 2>err || fail "batch: $(cat err)"
[[ $(status) == rendered ]] || fail "first batch: $(status)"
"$PRISM" batch b/jobs.json --quiet 2>err || fail "batch: $(cat err)"
[[ $(status) == skipped ]] && echo "ok: unchanged map skipped" || fail "re-run: $(status)"
cp big.exr b/sky.exr
"$PRISM" batch b/jobs.json --quiet 2>err || fail "batch: $(cat err)"
[[ $(status) == rendered ]] && echo "ok: changed map rendered again" || fail "changed map: $(status)"

echo "$failures failed"
[[ $failures -eq 0 ]]
