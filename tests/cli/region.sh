#!/usr/bin/env bash
# `prism render --region X0,Y0,X1,Y1`: only those pixels are rendered, each bit-identical to the
# same pixel of the whole frame (uniform, adaptive and with several threads and tile sizes); an
# EXR keeps the whole frame as its display window and the region as its data window; a PNG
# holds the region alone; bad regions are one-line usage errors with nothing written.
# Usage: region.sh PRISM SOURCE_DIR
source "$(dirname "$0")/lib/common.bash" "$@"
SCENE="$SRC/scenes/spheres.gltf"
PY=/usr/bin/python3
RES=(--res 96x64)

# region_matches FULL REGION X0 Y0 X1 Y1: the region file's data window is exactly the
# rectangle, its display window the full frame's, and its pixels the full frame's there.
region_matches() {
  "$PY" - "$@" <<'EOF'
import sys
import numpy as np
import OpenImageIO as oiio
full_path, region_path = sys.argv[1:3]
x0, y0, x1, y1 = map(int, sys.argv[3:7])
full = oiio.ImageBuf(full_path)
region = oiio.ImageBuf(region_path)
spec, fspec = region.spec(), full.spec()
window = (spec.x, spec.y, spec.x + spec.width, spec.y + spec.height)
display = (spec.full_x, spec.full_y, spec.full_width, spec.full_height)
errors = []
if window != (x0, y0, x1, y1):
    errors.append("data window %s, expected %s" % (window, (x0, y0, x1, y1)))
if display != (0, 0, fspec.width, fspec.height):
    errors.append("display window %s, expected the full frame %dx%d" % (display, fspec.width, fspec.height))
a = full.get_pixels(oiio.FLOAT)[y0:y1, x0:x1]
b = region.get_pixels(oiio.FLOAT)
if a.shape != b.shape or not np.array_equal(a, b):
    errors.append("pixels differ from the full frame's (max %s)" % (np.abs(a - b).max() if a.shape == b.shape else "shapes"))
if not (a[..., 3] > 0).any():
    errors.append("the region shows nothing: a test that could not fail")
print("; ".join(errors) if errors else "ok")
sys.exit(1 if errors else 0)
EOF
}

check_region() {
  local label=$1 x0=$2 y0=$3 x1=$4 y1=$5
  shift 5
  "$PRISM" render "$SCENE" "${RES[@]}" -q -o "$TMP/full.exr" "$@" || fail "$label: full render failed"
  "$PRISM" render "$SCENE" "${RES[@]}" -q -o "$TMP/region.exr" --region "$x0,$y0,$x1,$y1" "$@" ||
    fail "$label: region render failed"
  if out=$(region_matches "$TMP/full.exr" "$TMP/region.exr" "$x0" "$y0" "$x1" "$y1"); then
    echo "ok: $label: region $x0,$y0,$x1,$y1 matches the full frame"
  else
    fail "$label: $out"
  fi
}

# Corners off the 4-pixel packet grid and off the tile grid, and one pixel alone.
check_region "whitted, 16 spp" 13 7 61 45
check_region "whitted, 1 spp, 1 thread" 5 3 94 63 --spp 1 --threads 1
check_region "path, 4 spp, 2 threads" 30 10 31 11 --integrator path --spp 4 --threads 2
check_region "whole frame as a region" 0 0 96 64 --spp 2

# Adaptive: the region's pixels inside its edge have the full frame's neighbourhood, but its
# edge pixels do not; the interior is compared.
"$PRISM" render "$SCENE" "${RES[@]}" -q -o "$TMP/afull.exr" --spp 64 --target-error 0.05 ||
  fail "adaptive full render failed"
"$PRISM" render "$SCENE" "${RES[@]}" -q -o "$TMP/aregion.exr" --spp 64 --target-error 0.05 \
  --region 20,12,76,52 --sample-count-image "$TMP/acounts.exr" || fail "adaptive region failed"
if out=$("$PY" - "$TMP/afull.exr" "$TMP/aregion.exr" "$TMP/acounts.exr" <<'EOF'
import sys
import numpy as np
import OpenImageIO as oiio
full = oiio.ImageBuf(sys.argv[1]).get_pixels(oiio.FLOAT)
region = oiio.ImageBuf(sys.argv[2])
spec = region.spec()
counts = oiio.ImageBuf(sys.argv[3])
cspec = counts.spec()
errors = []
if (spec.x, spec.y, spec.width, spec.height) != (20, 12, 56, 40):
    errors.append("data window %s" % ((spec.x, spec.y, spec.width, spec.height),))
if (cspec.x, cspec.y, cspec.width, cspec.height) != (20, 12, 56, 40):
    errors.append("sample-count data window %s" % ((cspec.x, cspec.y, cspec.width, cspec.height),))
n = counts.get_pixels(oiio.FLOAT)[..., 0]
if not (n.min() >= 8 and n.max() <= 64 and n.min() < n.max()):
    errors.append("sample counts from %g to %g, expected adaptive counts in [8, 64]" % (n.min(), n.max()))
# Pixels further than the error estimate's neighbourhood (a few pixels) from the edge.
a = full[12 + 4:52 - 4, 20 + 4:76 - 4]
b = region.get_pixels(oiio.FLOAT)[4:-4, 4:-4]
if not np.array_equal(a, b):
    errors.append("interior pixels differ from the full frame's (%d of %d)" % ((a != b).any(axis=2).sum(), a.shape[0] * a.shape[1]))
print("; ".join(errors) if errors else "ok")
sys.exit(1 if errors else 0)
EOF
); then
  echo "ok: adaptive region: counts in its data window, interior pixels as the full frame's"
else
  fail "adaptive region: $out"
fi

# A PNG holds the region alone (no data window in PNG).
"$PRISM" render "$SCENE" "${RES[@]}" -q -o "$TMP/region.png" --region 10,20,50,44 ||
  fail "PNG region render failed"
size=$(oiiotool --info "$TMP/region.png" 2>/dev/null | grep -oE '[0-9]+ x +[0-9]+' | head -1 | tr -d ' ')
[[ $size == "40x24" ]] && echo "ok: PNG of the region is 40x24" || fail "PNG of the region is '$size', expected 40x24"

# Bad regions: one line, exit 2, nothing written.
expect_refused() {
  local pattern=$1
  shift
  rm -f "$TMP/bad.exr"
  expect 2 "$pattern" -- render "$SCENE" "${RES[@]}" -o "$TMP/bad.exr" "$@"
  [[ -e "$TMP/bad.exr" ]] && fail "$*: wrote an image anyway"
  return 0
}
expect_refused "--region 10,10,5,20: expected X0 < X1 and Y0 < Y1" --region 10,10,5,20
expect_refused "--region 1,2,3: expected X0,Y0,X1,Y1, four whole numbers" --region 1,2,3
expect_refused "--region 1,2,3,4,5: expected X0,Y0,X1,Y1" --region 1,2,3,4,5
expect_refused "--region -1,0,4,4: expected X0,Y0,X1,Y1" --region -1,0,4,4
expect_refused "--region 0,0,97,64: expected X0,Y0,X1,Y1 with 0 <= X0 < X1 <= 96 and 0 <= Y0 < Y1 <= 64" \
  --region 0,0,97,64

echo "$failures failed"
[[ $failures -eq 0 ]]
