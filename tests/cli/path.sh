#!/usr/bin/env bash
# The path integrator from the command line: the Cornell box lit only by its emissive panel
# renders, counts bounce rays, is bit-identical with 1 and 2 threads, stops adaptively with
# --time-limit, and refuses an out-of-range parameter with one line (exit 2).
# Usage: path.sh PRISM SOURCE_DIR
source "$(dirname "$0")/lib/common.bash" "$@"

SCENE="$SRC/scenes/cornell.gltf"
for threads in 1 2; do
  "$PRISM" render "$SCENE" -o "$TMP/t$threads.exr" --integrator path --res 32x32 --spp 4 \
    --threads "$threads" >"$TMP/stdout$threads" 2>"$TMP/stderr" ||
    fail "path render on $threads threads failed: $(cat "$TMP/stderr")"
done
grep -qE "bounce [1-9][0-9,]*" "$TMP/stdout1" || fail "no bounce rays counted: $(grep rays "$TMP/stdout1")"
"$PRISM" diff "$TMP/t1.exr" "$TMP/t2.exr" --metric max --fail-above 0 >/dev/null ||
  fail "1 and 2 threads differ"

"$PRISM" render "$SCENE" -o "$TMP/limited.exr" --integrator path --res 32x32 --spp 65536 \
  --time-limit 0.5 >"$TMP/stdout" 2>"$TMP/stderr" || fail "--time-limit render failed: $(cat "$TMP/stderr")"

expect 2 "strategy" -- render "$SRC/scenes/spheres.gltf" -o "$TMP/bad.exr" --integrator path --strategy 3

echo "$failures failed"
[[ $failures -eq 0 ]]
