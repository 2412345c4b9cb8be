#!/usr/bin/env bash
# Renders every glTF file of Debian's assimp-testmodels with each integrator at 160x120 and
# prints a Markdown table of the outcome (docs/results.md holds one run of it).
# Usage: scripts/assimp-table.sh [PRISM]
set -u
PRISM=${1:-build/apps/prism}
M=/usr/share/assimp/models/glTF2
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
echo "| file | phong | shadow | whitted | triangles; whitted's rays: camera / shadow / reflection / refraction |"
echo "| --- | --- | --- | --- | --- |"
while IFS= read -r f; do
  rel=${f#"$M"/}
  row="| \`$rel\` |"
  err=""
  for i in phong shadow whitted; do
    if out=$("$PRISM" render "$f" -o "$TMP/r.exr" --integrator "$i" --res 160x120 --verbose 2>"$TMP/err"); then
      row="$row ok |"
    else
      row="$row exit $? |"
      err=$(grep "prism: error" "$TMP/err" | sed "s|$M/||")
    fi
  done
  if [[ -z $err ]]; then
    tri=$(grep -o "[0-9]* triangles" "$TMP/err" | head -1)
    rays=$(grep "^rays " <<<"$out" |
      sed -E 's/rays +camera ([0-9,]+), shadow ([0-9,]+), reflection ([0-9,]+), refraction ([0-9,]+),.*/\1 \/ \2 \/ \3 \/ \4/')
    row="$row $tri; $rays |"
  else
    row="$row \`$err\` |"
  fi
  echo "$row"
done < <(find "$M" \( -name '*.gltf' -o -name '*.glb' \) | sort)
