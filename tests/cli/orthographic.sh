#!/usr/bin/env bash
# An orthographic camera's xmag and ymag: the default resolution has their ratio and gives
# no warning; a --res of another ratio keeps ymag and says so, once, on stderr.
# Usage: orthographic.sh PRISM SOURCE_DIR
source "$(dirname "$0")/lib/common.bash" "$@"

# A quad x in [-2.25, 1.5], y in [-1.5, 0.75] under a sun, seen from +Z with xmag 3, ymag 2.
cat >"$TMP/ortho.gltf" <<'JSON'
{"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0, 1, 2]}],
 "extensionsUsed": ["KHR_lights_punctual"],
 "extensions": {"KHR_lights_punctual": {"lights": [{"type": "directional", "intensity": 3}]}},
 "nodes": [{"mesh": 0}, {"extensions": {"KHR_lights_punctual": {"light": 0}}},
           {"camera": 0, "translation": [0, 0, 10]}],
 "cameras": [{"name": "wide", "type": "orthographic",
              "orthographic": {"xmag": 3, "ymag": 2, "znear": 0.01, "zfar": 100}}],
 "materials": [{"pbrMetallicRoughness": {"metallicFactor": 0}}],
 "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 0}]}],
 "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
                "min": [-2.25, -1.5, 0], "max": [1.5, 0.75, 0]},
               {"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"}],
 "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48},
                 {"buffer": 0, "byteOffset": 48, "byteLength": 12}],
 "buffers": [{"byteLength": 60, "uri": "data:application/octet-stream;base64,AAAQwAAAwL8AAAAAAADAPwAAwL8AAAAAAADAPwAAQD8AAAAAAAAQwAAAQD8AAAAAAAABAAIAAAACAAMA"}]}
JSON

"$PRISM" render "$TMP/ortho.gltf" -o "$TMP/default.exr" --integrator shadow \
  >"$TMP/stdout" 2>"$TMP/stderr" || fail "default resolution did not render: $(cat "$TMP/stderr")"
[[ -s "$TMP/stderr" ]] && fail "default resolution warned: $(cat "$TMP/stderr")"
grep -q "^rendered .*, 720x480," "$TMP/stdout" || fail "not 720x480 (xmag/ymag 1.5): $(head -1 "$TMP/stdout")"

"$PRISM" render "$TMP/ortho.gltf" -o "$TMP/wide.exr" --integrator shadow --res 800x400 \
  >"$TMP/stdout" 2>"$TMP/stderr" || fail "800x400 did not render: $(cat "$TMP/stderr")"
expected="prism: warning: $TMP/ortho.gltf: camera 'wide' is orthographic with xmag 3 and ymag 2, a 1.5:1 view, but the image is 800x400: ymag kept, xmag 3 widened to 4 so that pixels stay square"
[[ "$(cat "$TMP/stderr")" == "$expected" ]] || fail "800x400: stderr is '$(cat "$TMP/stderr")', expected '$expected'"

"$PRISM" render "$TMP/ortho.gltf" -o "$TMP/narrow.exr" --integrator shadow --res 500x400 \
  >"$TMP/stdout" 2>"$TMP/stderr" || fail "500x400 did not render: $(cat "$TMP/stderr")"
grep -qF "ymag kept, xmag 3 narrowed to 2.5 so that pixels stay square" "$TMP/stderr" ||
  fail "500x400: stderr is '$(cat "$TMP/stderr")'"

echo "$failures failed"
[[ $failures -eq 0 ]]
