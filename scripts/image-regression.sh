#!/usr/bin/env bash
# Renders every shipped scene (each sphere mode) and every glTF file of Debian's
# assimp-testmodels with phong, shadow and whitted at 1 and 2 threads into OUT_DIR, so that
# two builds can be compared image by image (`idiff -fail 0`) across a restructuring.
# Usage: scripts/image-regression.sh PRISM OUT_DIR      (renders)
#        scripts/image-regression.sh --compare A_DIR B_DIR   (prints differing images, exit 1 if any)
set -u
if [[ ${1:-} == --compare ]]; then
  bad=0 same=0
  for a in "$2"/*.exr; do
    b="$3/$(basename "$a")"
    if [[ ! -f $b ]]; then echo "missing: $b"; bad=$((bad + 1)); continue; fi
    if idiff -fail 0 -warn 0 "$a" "$b" >/dev/null 2>&1; then same=$((same + 1)); else
      echo "differs: $(basename "$a")"; bad=$((bad + 1)); fi
  done
  echo "identical: $same, differing or missing: $bad"
  [[ $bad == 0 ]]
  exit
fi
PRISM=$1
OUT=$2
ROOT=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$OUT"
render() { # name scene extra-args...
  local name=$1 scene=$2
  shift 2
  for integrator in phong shadow whitted; do
    for threads in 1 2; do
      "$PRISM" render "$scene" -o "$OUT/$name.$integrator.t$threads.exr" --integrator "$integrator" \
        --threads "$threads" --quiet "$@" 2>/dev/null || echo "failed: $name $integrator t$threads" >&2
    done
  done
}
for scene in "$ROOT"/scenes/*.gltf; do
  base=$(basename "$scene" .gltf)
  for mode in analytic mesh:2 embree-points; do
    render "$base.${mode/:/}" "$scene" --res 160x120 --spp 4 --spheres "$mode"
  done
done
while IFS= read -r file; do
  rel=${file#/usr/share/assimp/models/glTF2/}
  render "assimp.${rel//\//_}" "$file" --res 96x72 --spp 2
done < <(find /usr/share/assimp/models/glTF2 -name '*.gl*' | sort)
