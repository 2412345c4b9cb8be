#!/usr/bin/env bash
# Every glTF file in Debian's assimp-testmodels renders with each integrator, or, for the
# files listed below, fails with one clear line naming the file (exit 1) and writes nothing.
# Usage: assimp_models.sh PRISM SOURCE_DIR
set -u
PRISM=$1
MODELS=/usr/share/assimp/models/glTF2
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT

# Files that must be refused, and why. (draco/2CylinderEngine.gltf renders since
# KHR_draco_mesh_compression is decoded; skins, morph targets and spec-gloss files render their
# rest pose and converted materials.)
declare -A EXPECTED_ERROR=(
  [BoxTextured-glTF-techniqueWebGL/BoxTextured.gltf]="extensionsRequired"      # KHR_technique_webgl
  [BoxWithInfinites-glTF-Binary/BoxWithInfinites.glb]="accessors\[[0-9]+\]"     # infinite positions
  [IncorrectVertexArrays/Cube.gltf]="meshes\[1\].primitives\[0\]"               # 35 vertices, TRIANGLES
  [IndexOutOfRange/AllIndicesOutOfRange.gltf]="meshes\[0\].primitives\[0\].indices"
  [IndexOutOfRange/IndexOutOfRange.gltf]="meshes\[0\].primitives\[0\].indices"
  [MissingBin/BoxTextured.gltf]="buffers\[0\]"
  [RecursiveNodes/RecursiveNodes.gltf]="nodes\[[0-9]+\]"
  [SchemaFailures/sceneWrongType.gltf]="scene"
  [TestNoRootNode/NoScene.gltf]="scene"
  [wrongTypes/badArray.gltf]="meshes\[0\].primitives"
  [wrongTypes/badExtension.gltf]="materials\[0\]"
  [wrongTypes/badNumber.gltf]="materials\[0\]"
  [wrongTypes/badObject.gltf]="materials\[0\].pbrMetallicRoughness"
  [wrongTypes/badString.gltf]="scenes\[0\].name"
  [wrongTypes/badUint.gltf]="materials\[0\]"
)

failures=0
rendered=0
refused=0
while IFS= read -r file; do
  rel=${file#"$MODELS"/}
  for integrator in phong shadow whitted; do
    out="$TMP/out.exr"
    rm -f "$out"
    "$PRISM" render "$file" -o "$out" --integrator "$integrator" --res 48x36 --quiet \
      2>"$TMP/err" >/dev/null
    code=$?
    errors=$(grep -c "^prism: error:" "$TMP/err")
    if [[ -n "${EXPECTED_ERROR[$rel]+x}" ]]; then
      if [[ $code -ne 1 || $errors -ne 1 || -e "$out" ]] ||
        ! grep -qE "^prism: error: $file: ${EXPECTED_ERROR[$rel]}" "$TMP/err"; then
        echo "FAIL ($integrator): $rel should be refused with '${EXPECTED_ERROR[$rel]}'; exit $code:"
        cat "$TMP/err"
        failures=$((failures + 1))
      else
        refused=$((refused + 1))
      fi
    else
      if [[ $code -ne 0 || ! -s "$out" ]]; then
        echo "FAIL ($integrator): $rel did not render (exit $code):"
        cat "$TMP/err"
        failures=$((failures + 1))
      else
        rendered=$((rendered + 1))
      fi
    fi
  done
done < <(find "$MODELS" \( -name '*.gltf' -o -name '*.glb' \) | sort)

echo "rendered: $rendered, refused as expected: $refused"
echo "$((rendered + refused)) passed, $failures failed"
[[ $failures -eq 0 && $rendered -gt 0 ]]
