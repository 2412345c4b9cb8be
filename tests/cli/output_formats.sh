#!/usr/bin/env bash
# -o chooses the format by extension: EXR (scene-linear master), TIFF and HDR (scene-linear,
# through the OpenImageIO module), PNG and JPEG (display-referred through --view, after
# --exposure); prism info --views lists the config's views, $OCIO's too; an output that
# cannot be written is refused before the render. Usage: output_formats.sh PRISM SOURCE_DIR
source "$(dirname "$0")/lib/common.bash" "$@"

SCENE="$SRC/scenes/spheres.gltf"
render() { "$PRISM" render "$SCENE" --res 32x24 -q "$@"; }

render -o "$TMP/m.exr" || fail "EXR render"
for ext in tif tiff hdr png jpg jpeg JPG; do
  render -o "$TMP/m.$ext" || fail "render -o m.$ext"
done
iinfo "$TMP/m.tif" | grep -qF "32 x   24, 4 channel, float tiff" || fail "TIFF: $(iinfo "$TMP/m.tif")"
iinfo "$TMP/m.tiff" | grep -qF "4 channel, float tiff" || fail "TIFF: $(iinfo "$TMP/m.tiff")"
iinfo "$TMP/m.hdr" | grep -qF "32 x   24, 3 channel, float hdr" || fail "HDR: $(iinfo "$TMP/m.hdr")"
iinfo "$TMP/m.png" | grep -qF "32 x   24, 3 channel, uint8 png" || fail "PNG: $(iinfo "$TMP/m.png")"
iinfo "$TMP/m.jpg" | grep -qF "32 x   24, 3 channel, uint8 jpeg" || fail "JPEG: $(iinfo "$TMP/m.jpg")"
iinfo "$TMP/m.JPG" | grep -qF "uint8 jpeg" || fail "JPEG by .JPG: $(iinfo "$TMP/m.JPG")"

# Scene-linear outputs hold the EXR's own values; the PNG is the EXR through the view.
[[ "$(idiff -fail 1e-6 "$TMP/m.exr" "$TMP/m.tif" >/dev/null; echo $?)" == 0 ]] || fail "TIFF differs from the EXR"
oiiotool "$TMP/m.exr" --ch R,G,B -o "$TMP/m-rgb.exr"  # HDR has no alpha
[[ "$(idiff -fail 0.01 -failrelative 0.01 "$TMP/m-rgb.exr" "$TMP/m.hdr" >/dev/null; echo $?)" == 0 ]] || fail "HDR differs from the EXR beyond its 8-bit mantissa"
render -o "$TMP/p.exr" --preview "$TMP/p.png" || fail "preview render"
[[ "$(idiff -fail 0 "$TMP/p.png" "$TMP/m.png" >/dev/null; echo $?)" == 0 ]] || fail "-o x.png differs from --preview"

# --exposure brightens, --view ACES rolls off: the mean of the display image moves as expected.
mean() { oiiotool "$1" --printstats 2>/dev/null | sed -n 's/^ *Stats Avg: \([0-9.]*\) .*/\1/p' | head -1; }
render -o "$TMP/bright.png" --exposure 2 || fail "--exposure 2"
render -o "$TMP/dark.png" --exposure -2 || fail "--exposure -2"
render -o "$TMP/aces.png" --view "ACES 1.0 SDR-video" || fail "--view ACES"
python3 - "$(mean "$TMP/dark.png")" "$(mean "$TMP/m.png")" "$(mean "$TMP/bright.png")" "$(mean "$TMP/aces.png")" <<'PY' || fail "display means out of order: dark < standard < bright, ACES differs from Standard"
import sys
dark, standard, bright, aces = map(float, sys.argv[1:])
print("means: dark", dark, "standard", standard, "bright", bright, "aces", aces)
sys.exit(0 if dark < standard < bright and abs(aces - standard) > 1e-3 else 1)
PY
expect 2 "^prism: error: --view Filmic: display 'sRGB - Display' of OCIO config built-in has the views Standard, ACES 1.0 SDR-video, Raw$" -- render "$SCENE" -o "$TMP/v.png" --view Filmic
expect 2 "^prism: error: --exposure nan: must be a number of stops from -64 to 64$" -- render "$SCENE" -o "$TMP/v.png" --exposure nan
expect 2 "^prism: error: --output $TMP/v.gif: the file name must end in .exr, .tif, .tiff, .hdr, .png, .jpg or .jpeg$" -- render "$SCENE" -o "$TMP/v.gif"
[[ -e "$TMP/v.png" ]] && fail "a refused render wrote its output"

# prism info --views: the shipped config's, and a user's $OCIO config's own.
"$PRISM" info --views >"$TMP/views" || fail "info --views exited $?"
grep -qx "  sRGB - Display / Standard (default)" "$TMP/views" || fail "info --views: $(cat "$TMP/views")"
grep -qx "  sRGB - Display / ACES 1.0 SDR-video" "$TMP/views" || fail "info --views has no ACES view"
sed 's/name: Raw, colorspace: Raw}/name: Raw, colorspace: Raw}\n    - !<View> {name: Flat, colorspace: Raw}/; s/active_views: \[Standard, ACES 1.0 SDR-video, Raw\]/active_views: [Standard, ACES 1.0 SDR-video, Raw, Flat]/' \
  "$SRC/renderer/image/ocio/config.ocio" >"$TMP/user.ocio"
OCIO="$TMP/user.ocio" "$PRISM" info --views >"$TMP/views" || fail "OCIO=user info --views exited $?"
grep -qx "OCIO config: \$OCIO=$TMP/user.ocio" "$TMP/views" || fail "user config not named: $(cat "$TMP/views")"
grep -qx "  sRGB - Display / Flat" "$TMP/views" || fail "user config's view missing: $(cat "$TMP/views")"
OCIO="$TMP/user.ocio" render -o "$TMP/flat.png" --view Flat || fail "--view of a user's config"
expect 2 "^prism: error: a scene file is required \(or --views\)$" -- info

# An output that cannot be written is refused before anything renders; nothing is left there.
expect 2 "^prism: error: --output /proc/prism-out.exr: cannot be written: " -- render "$SCENE" -o /proc/prism-out.exr --spp 4096
expect 2 "^prism: error: --preview /proc/prism-out.png: cannot be written: " -- render "$SCENE" -o "$TMP/w.exr" --preview /proc/prism-out.png
[[ -e "$TMP/w.exr" ]] && fail "a render refused for its preview wrote its image"
ls -A "$TMP" | grep -q "tmp-" && fail "temporary files left behind: $(ls -A "$TMP")"

# --half and --compression shape EXR files only: with a PNG or TIFF output each is one warning
# line, said before the render, and the file is written; with an EXR, none.
for option in "--half" "--compression zip"; do
  "$PRISM" render "$SCENE" --res 32x24 --spp 1 -o "$TMP/h.png" $option >/dev/null 2>"$TMP/err" ||
    fail "$option with a PNG output exited $?"
  name=${option%% *}
  if [[ $(grep -c "^prism: warning: $name sets how EXR files are stored; $TMP/h.png is not one" "$TMP/err") -ne 1 ]]; then
    fail "$option with a PNG output: no single warning: $(cat "$TMP/err")"
  else
    echo "ok: $option with a PNG output warns once"
  fi
  [[ -s "$TMP/h.png" ]] || fail "$option with a PNG output wrote nothing"
  rm -f "$TMP/h.png"
  "$PRISM" render "$SCENE" --res 32x24 --spp 1 -o "$TMP/h.exr" $option >/dev/null 2>"$TMP/err" ||
    fail "$option with an EXR output exited $?"
  grep -q "sets how EXR files are stored" "$TMP/err" && fail "$option with an EXR output warned: $(cat "$TMP/err")"
done
"$PRISM" render "$SCENE" --res 32x24 --spp 1 -o "$TMP/h.tif" --half -q >/dev/null 2>"$TMP/err" || fail "-q --half .tif exited $?"
[[ -s "$TMP/err" ]] && fail "-q still warned: $(cat "$TMP/err")"

# The default render is anti-aliased: 16 samples per pixel, recorded in the EXR; --spp 1 is
# the lecture's pixel-centre rays.
"$PRISM" render "$SCENE" --res 32x24 -q -o "$TMP/default.exr" || fail "default render exited $?"
"$PRISM" render "$SCENE" --res 32x24 -q --spp 1 -o "$TMP/one.exr" || fail "--spp 1 render exited $?"
spp=$(oiiotool --info -v "$TMP/default.exr" | sed -n 's/^ *prism:spp: //p')
[[ $spp == 16 ]] && echo "ok: default render takes 16 spp" || fail "default render's prism:spp is '$spp', expected 16"
spp=$(oiiotool --info -v "$TMP/one.exr" | sed -n 's/^ *prism:spp: //p')
[[ $spp == 1 ]] || fail "--spp 1 render's prism:spp is '$spp'"
"$PRISM" render --help | grep -qE -- "--spp INT.*=16( |$)" && echo "ok: --help shows the default 16" ||
  fail "render --help does not show --spp's default 16: $("$PRISM" render --help | grep -- --spp)"

echo "$failures failed"
[[ $failures -eq 0 ]]
