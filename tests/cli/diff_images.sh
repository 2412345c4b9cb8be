#!/usr/bin/env bash
# prism diff A B -o DIFF.exr writes |A - B| (as idiff -o does) and --heatmap a false-colour
# PNG, white at the largest error. Usage: diff_images.sh PRISM SOURCE_DIR
source "$(dirname "$0")/lib/common.bash" "$@"

SCENE="$SRC/scenes/spheres.gltf"
"$PRISM" render "$SCENE" -o "$TMP/a.exr" --res 40x30 --integrator phong -q || fail "render a"
"$PRISM" render "$SCENE" -o "$TMP/b.exr" --res 40x30 --integrator whitted -q || fail "render b"
"$PRISM" diff "$TMP/a.exr" "$TMP/b.exr" -o "$TMP/d.exr" --heatmap "$TMP/h.png" >"$TMP/out" || fail "diff -o exited $?"
grep -q "^heat map $TMP/h.png: white at an error of " "$TMP/out" || fail "no heat map line: $(cat "$TMP/out")"
# The difference equals idiff's own, and its largest value is the table's max error.
idiff -o "$TMP/idiff.exr" -abs "$TMP/a.exr" "$TMP/b.exr" >/dev/null
oiiotool "$TMP/idiff.exr" --ch R,G,B -o "$TMP/idiff-rgb.exr"
oiiotool "$TMP/d.exr" --ch R,G,B -o "$TMP/d-rgb.exr"
idiff -fail 1e-6 "$TMP/d-rgb.exr" "$TMP/idiff-rgb.exr" >/dev/null || fail "the difference differs from idiff -o -abs"
max=$(sed -n 's/^RGB .* \([0-9.e+-]*\)  ([0-9]*, [0-9]*, [RGB])$/\1/p' "$TMP/out")
peak=$(sed -n 's/^heat map .*: white at an error of //p' "$TMP/out")
[[ -n "$max" && "$max" == "$peak" ]] || fail "heat map peak $peak is not the max error $max"
iinfo "$TMP/h.png" | grep -qF "40 x   30, 3 channel, uint8 png" || fail "heat map: $(iinfo "$TMP/h.png")"
# Equal images: an all-zero difference and an all-black heat map.
"$PRISM" diff "$TMP/a.exr" "$TMP/a.exr" -o "$TMP/z.exr" --heatmap "$TMP/z.png" -q || fail "diff of equal images"
oiiotool "$TMP/z.png" --printstats | grep -q "Stats Max: 0 0 0" || fail "heat map of equal images is not black"
expect 2 "^prism: error: -o $TMP/d.png: the file name must end in .exr$" -- diff "$TMP/a.exr" "$TMP/b.exr" -o "$TMP/d.png"
expect 2 "^prism: error: --heatmap $TMP/h.exr: the file name must end in .png$" -- diff "$TMP/a.exr" "$TMP/b.exr" --heatmap "$TMP/h.exr"

echo "$failures failed"
[[ $failures -eq 0 ]]
