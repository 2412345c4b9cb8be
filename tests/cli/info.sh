#!/usr/bin/env bash
# `prism info`: on every glTF 2.0 file Debian's assimp-testmodels ships, it either prints
# every section and exits 0, or prints one line naming the file and exits 1; exact content
# for scenes/spheres.gltf; exit code 2 for a bad command line.
# Usage: info.sh PRISM SOURCE_DIR
source "$(dirname "$0")/lib/common.bash" "$@"

SECTIONS=(file scenes meshes materials textures lights cameras spheres extensions features warnings)

ASSIMP=/usr/share/assimp/models/glTF2
if [[ -d $ASSIMP ]]; then
  count=0
  while IFS= read -r -d '' file; do
    count=$((count + 1))
    "$PRISM" info "$file" >"$TMP/out" 2>"$TMP/err"
    rc=$?
    if [[ $rc -eq 0 ]]; then
      for s in "${SECTIONS[@]}"; do
        grep -q "^$s[ :(]" "$TMP/out" || fail "$file: exit 0 but no '$s' section"
      done
    elif [[ $rc -eq 1 ]]; then
      [[ $(wc -l <"$TMP/err") -eq 1 ]] || fail "$file: exit 1 with $(wc -l <"$TMP/err") lines on stderr"
      grep -qF "$file" "$TMP/err" || fail "$file: the error does not name the file: $(cat "$TMP/err")"
    else
      fail "$file: exit code $rc: $(head -3 "$TMP/err")"
    fi
  done < <(find "$ASSIMP" \( -name '*.gltf' -o -name '*.glb' \) -print0)
  echo "info on $count assimp-testmodels files"
  [[ $count -gt 20 ]] || fail "only $count files found under $ASSIMP"
else
  echo "skipping assimp-testmodels: $ASSIMP not found"
fi

# Exact content of the shipped default scene.
out=$("$PRISM" info "$SRC/scenes/spheres.gltf") || fail "spheres.gltf: exit code $?"
expect() { grep -qxF -- "$1" <<<"$out" || fail "spheres.gltf: no line '$1'"; }
expect "spheres: 4"
expect "lights: 2"
expect "cameras: 1"
expect "materials: 6"
expect "textures: 1"
expect "warnings: 0"
expect "meshes: 2 (2 placed by 2 nodes, 0 instanced), 4 triangles as placed"
expect "  [0] main: perspective, yfov 37.24 deg, aspect 1.778"
expect "  [0] checker: 256x256, 3 channels, sRGB, wrap repeat/repeat"
expect "      base colour texture [0] checker (sRGB)"
expect "  [0] key: point, 60 cd, colour (1, 0.95, 0.88), at (3, 5, 4)"
expect "  [1] glass sphere: centre (1.15, 0.8, 0.9), radius 0.8, material glass"
expect "extensions: used KHR_materials_transmission, KHR_materials_ior, PRISM_sphere, KHR_lights_punctual; required none"
expect "features (spheres analytic): geometry=triangles+analytic-spheres lights=positional textures=base-colour mirror=yes transmission=yes emission=no alpha=none shadows=yes"
grep -q '^  \[1\] sky: directional, 0.8 lx' <<<"$out" || fail "spheres.gltf: sky light not in lux"

# The sphere mode changes the feature set; one sphere lit from inside cannot shadow itself.
"$PRISM" info "$SRC/scenes/spheres.gltf" --spheres mesh:2 | grep -q "^features (spheres mesh:2): geometry=triangles+sphere-meshes " ||
  fail "--spheres mesh:2 not reflected in the features"
"$PRISM" info "$SRC/scenes/furnace.gltf" | grep -q "shadows=no$" || fail "furnace.gltf: shadows should be no"

# Scenes: listed, default marked, --scene by name or index, a missing scene is a usage error.
cat >"$TMP/scenes.gltf" <<'EOF'
{"asset": {"version": "2.0"}, "scene": 1,
 "scenes": [{"name": "day", "nodes": [0]}, {"name": "night", "nodes": [1, 2]}],
 "nodes": [{"name": "a"}, {"name": "b"}, {"name": "c"}]}
EOF
out=$("$PRISM" info "$TMP/scenes.gltf") || fail "scenes.gltf: exit code $?"
grep -qxF "scenes: 2 (loaded: 1)" <<<"$out" || fail "scenes.gltf: no 'scenes: 2 (loaded: 1)': $out"
grep -qxF "  [1] night: 2 root nodes, default, loaded" <<<"$out" || fail "scenes.gltf: scene 1 line"
grep -qxF "  [0] day: 1 root node" <<<"$out" || fail "scenes.gltf: scene 0 line"
for s in day 0; do
  "$PRISM" info "$TMP/scenes.gltf" --scene "$s" | grep -qxF "  [0] day: 1 root node, loaded" ||
    fail "--scene $s: scene 0 not loaded"
done
for s in 2 -1 dusk 99999999999999999999999; do
  "$PRISM" info "$TMP/scenes.gltf" --scene "$s" >"$TMP/out" 2>"$TMP/err"; rc=$?
  [[ $rc -eq 2 && $(wc -l <"$TMP/err") -eq 1 && ! -s $TMP/out ]] ||
    fail "--scene $s: exit $rc, expected 2 with one line: $(cat "$TMP/err")"
  grep -qF "no scene '$s' (the file has 2 scenes: 0 'day', 1 'night'; give a name or an index from 0 to 1)" "$TMP/err" ||
    fail "--scene $s: message $(cat "$TMP/err")"
done
"$PRISM" render "$TMP/scenes.gltf" --scene dusk -o "$TMP/s.exr" >/dev/null 2>"$TMP/err"; rc=$?
[[ $rc -eq 2 && ! -e $TMP/s.exr ]] || fail "render --scene dusk: exit $rc, expected 2"
"$PRISM" info "$SRC/scenes/spheres.gltf" --timing |
  grep -qE "^timing: load [0-9.]+ s, BVH build [0-9.]+ s, total [0-9.]+ s; 4 triangles built \(0 degenerate and 0 non-finite dropped\); peak memory" ||
  fail "--timing: no timing line"

# Usage errors exit 2, a broken file 1 with one line naming it.
"$PRISM" info >/dev/null 2>&1; rc=$?
[[ $rc -eq 2 ]] || fail "no scene: exit code $rc, expected 2"
"$PRISM" info "$SRC/scenes/spheres.gltf" --spheres bogus >/dev/null 2>&1; rc=$?
[[ $rc -eq 2 ]] || fail "--spheres bogus: exit code $rc, expected 2"
echo '{"asset": {"version": "2.0"}, "meshes": [' >"$TMP/broken.gltf"
"$PRISM" info "$TMP/broken.gltf" >"$TMP/out" 2>"$TMP/err"; rc=$?
[[ $rc -eq 1 ]] || fail "broken.gltf: exit code $rc, expected 1"
[[ $(wc -l <"$TMP/err") -eq 1 ]] && grep -qF "$TMP/broken.gltf" "$TMP/err" ||
  fail "broken.gltf: expected one line naming the file, got: $(cat "$TMP/err")"
[[ ! -s $TMP/out ]] || fail "broken.gltf: printed a partial report on stdout"

# render --verbose prints the feature set, and the EXR records it.
"$PRISM" render "$SRC/scenes/furnace.gltf" -o "$TMP/f.exr" --res 16x16 --verbose --quiet 2>"$TMP/err" ||
  fail "render --verbose: exit code $?"
grep -qx "prism: features: geometry=analytic-spheres lights=positional textures=none mirror=no transmission=no emission=no alpha=none shadows=no" "$TMP/err" ||
  fail "render --verbose: no features line: $(cat "$TMP/err")"
if command -v oiiotool >/dev/null; then
  meta=$(oiiotool --info -v "$TMP/f.exr")
  grep -q 'prism:featureShadows: "no"' <<<"$meta" || fail "EXR: no prism:featureShadows \"no\": $meta"
  grep -q 'prism:features: "geometry=analytic-spheres ' <<<"$meta" || fail "EXR: no prism:features"
fi

echo "$failures failed"
[[ $failures -eq 0 ]]
