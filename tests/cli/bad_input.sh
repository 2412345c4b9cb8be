#!/usr/bin/env bash
# Bad input to `prism render`: a clear one-line error, the right exit code, and no output
# file created or clobbered. Usage: bad_input.sh PRISM SOURCE_DIR
source "$(dirname "$0")/lib/common.bash" "$@"

SCENE="$SRC/scenes/spheres.gltf"
BROKEN=/usr/share/assimp/models/glTF2

expect 1 "no-such-scene.gltf" -- render "$TMP/no-such-scene.gltf" -o "$TMP/a.exr"
expect 2 "--integrator" -- render "$SCENE" -o "$TMP/a.exr" --integrator pathtracer
expect 2 "spp" -- render "$SCENE" -o "$TMP/a.exr" --spp 0
expect 2 "--res" -- render "$SCENE" -o "$TMP/a.exr" --res 100by100
expect 2 "--res" -- render "$SCENE" -o "$TMP/a.exr" --res 0x10
expect 2 "--spheres" -- render "$SCENE" -o "$TMP/a.exr" --spheres cubes
expect 2 "--working-space" -- render "$SCENE" -o "$TMP/a.exr" --working-space xyz
expect 2 "does not exist" -- render "$SCENE" -o "$TMP/missing-dir/a.exr"
expect 2 "must end in .exr, .tif, .tiff, .hdr, .png, .jpg or .jpeg" -- render "$SCENE" -o "$TMP/a.gif"
expect 2 "must end in .png" -- render "$SCENE" -o "$TMP/a.exr" --preview "$TMP/a.jpg"
expect 2 "--camera nope" -- render "$SCENE" -o "$TMP/a.exr" --camera nope
expect 2 "--camera 7" -- render "$SCENE" -o "$TMP/a.exr" --camera 7
expect 2 "ambient" -- render "$SCENE" -o "$TMP/a.exr" --ambient nan
expect 2 "threads" -- render "$SCENE" -o "$TMP/a.exr" --threads -3
expect 2 "error" -- render "$SCENE"
expect 2 "error" -- frobnicate
expect 1 "IndexOutOfRange.gltf: .*indices" -- render "$BROKEN/IndexOutOfRange/IndexOutOfRange.gltf" -o "$TMP/a.exr"
expect 1 "BoxTextured.gltf: .*buffers\[0\]" -- render "$BROKEN/MissingBin/BoxTextured.gltf" -o "$TMP/a.exr"
expect 1 "BoxWithInfinites.glb: accessors\[[0-9]+\]" -- render "$BROKEN/BoxWithInfinites-glTF-Binary/BoxWithInfinites.glb" -o "$TMP/a.exr"
expect 1 "RecursiveNodes.gltf: nodes\[[0-9]+\]" -- render "$BROKEN/RecursiveNodes/RecursiveNodes.gltf" -o "$TMP/a.exr"

# A buffer outside the scene's folder is refused unless --allow-external-paths.
mkdir -p "$TMP/scene" "$TMP/elsewhere"
printf '\0\0\0\0\0\0\0\0\0\0\0\0\0\0\200\077\0\0\0\0\0\0\0\0\0\0\0\0\0\0\200\077\0\0\0\0' >"$TMP/elsewhere/data.bin"
cat >"$TMP/scene/tri.gltf" <<'GLTF'
{"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
 "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
 "buffers": [{"byteLength": 36, "uri": "../elsewhere/data.bin"}],
 "bufferViews": [{"buffer": 0, "byteLength": 36}],
 "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                "min": [0, 0, 0], "max": [1, 1, 0]}]}
GLTF
expect 1 "tri.gltf: buffers\[0\].uri: .*outside" -- render "$TMP/scene/tri.gltf" -o "$TMP/a.exr"
if ! "$PRISM" render "$TMP/scene/tri.gltf" -o "$TMP/ext.exr" --allow-external-paths -q 2>/dev/null; then
  echo "FAIL: --allow-external-paths did not let the buffer load"; failures=$((failures + 1))
fi

if [[ -e "$TMP/a.exr" ]]; then
  echo "FAIL: a failed render left $TMP/a.exr behind"; failures=$((failures + 1))
fi

# A failed render must not clobber an existing output.
echo "precious" >"$TMP/keep.exr"
"$PRISM" render "$BROKEN/IndexOutOfRange/IndexOutOfRange.gltf" -o "$TMP/keep.exr" 2>/dev/null
if [[ "$(cat "$TMP/keep.exr")" != "precious" ]]; then
  echo "FAIL: a failed render overwrote an existing file"; failures=$((failures + 1))
fi
if ls -A "$TMP" | grep -q "tmp-"; then
  echo "FAIL: temporary files left behind: $(ls -A "$TMP")"; failures=$((failures + 1))
fi

# --help works and exits 0.
if ! "$PRISM" render --help | grep -q -- "--integrator"; then
  echo "FAIL: prism render --help"; failures=$((failures + 1))
fi

echo "$failures failed"
[[ $failures -eq 0 ]]
