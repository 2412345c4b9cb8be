#!/usr/bin/env bash
# What `prism render` writes: identical pixels whatever the thread count, the EXR's
# chromaticities and metadata, the PNG preview, and a silent stderr when not on a terminal.
# Usage: render_outputs.sh PRISM SOURCE_DIR
source "$(dirname "$0")/lib/common.bash" "$@"
SCENE="$SRC/scenes/spheres.gltf"

for integrator in phong shadow whitted; do
  for threads in 1 2; do
    "$PRISM" render "$SCENE" -o "$TMP/$integrator-$threads.exr" --integrator "$integrator" \
      --threads "$threads" --spp 2 --res 160x90 >"$TMP/stdout" 2>"$TMP/stderr" ||
      fail "$integrator with $threads threads did not render"
    # Not a terminal: no progress bar, and this scene gives no warnings.
    [[ -s "$TMP/stderr" ]] && fail "stderr not empty off a terminal: $(cat "$TMP/stderr")"
    grep -q "^rays .*camera 28,800" "$TMP/stdout" || fail "summary lacks the camera ray count"
    grep -q "^rays/second" "$TMP/stdout" || fail "summary lacks rays/second"
  done
  # Bit-identical pixels (the files differ only in their timing metadata).
  idiff -fail 0 -failpercent 0 -warn 0 "$TMP/$integrator-1.exr" "$TMP/$integrator-2.exr" >/dev/null ||
    fail "$integrator: 1 and 2 threads differ"
done

info=$(iinfo -v "$TMP/whitted-1.exr")
# The default, auto, builds this small scene at high: 172,800 expected rays for its few
# primitives. The metadata names the quality built, not the request.
for expected in "chromaticities: 0.64, 0.33, 0.3, 0.6, 0.15, 0.06, 0.3127, 0.329" \
  'prism:integrator: "whitted"' "prism:spp: 2" 'Software: "prism' "worldToCamera:" \
  'prism:buildQuality: "high"' 'prism:robust: "0"' \
  "worldToNDC:" "prism:renderSeconds:" 'prism:workingSpace: "linear-rec709"' \
  "160 x   90, 4 channel, float openexr"; do
  grep -qF "$expected" <<<"$info" || fail "EXR lacks '$expected'"
done

"$PRISM" render "$SCENE" -o "$TMP/aces.exr" --working-space acescg --half --res 32x18 --quiet \
  --preview "$TMP/aces.png" || fail "acescg render"
info=$(iinfo -v "$TMP/aces.exr")
grep -qF "chromaticities: 0.713, 0.293, 0.165, 0.83, 0.128, 0.044, 0.32168, 0.33767" <<<"$info" ||
  fail "ACEScg EXR lacks AP1 chromaticities: $(grep chromaticities <<<"$info")"
grep -qF "half openexr" <<<"$info" || fail "--half did not write half floats"
iinfo "$TMP/aces.png" | grep -qF "32 x   18, 3 channel, uint8 png" || fail "PNG preview: $(iinfo "$TMP/aces.png")"

echo "$failures failed"
[[ $failures -eq 0 ]]
