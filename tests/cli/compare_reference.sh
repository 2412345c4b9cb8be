#!/usr/bin/env bash
# `prism compare` without --reference: one converged `path` render is every integrator's
# reference (rendered once, cached, and its row the only reference row), so each row's error
# is its bias and its noise; a heat map per row on one scale; equal-time and equal-error
# side-by-sides in results.json; the terminal table within 100 columns even with long names;
# one warm-up per BVH. Usage: compare_reference.sh PRISM SOURCE_DIR
source "$(dirname "$0")/lib/common.bash" "$@"
SCENE="$SRC/scenes/cornell.gltf"
PY=/usr/bin/python3
export XDG_CACHE_HOME="$TMP/cache"
ARGS=(compare "$SCENE" --res 48x48 --spp 1,4,16 --integrators whitted,shadow,path
  --target-errors 0.005 --spheres analytic,embree-points --reference-spp 64 --threads 2)

"$PRISM" "${ARGS[@]}" -o "$TMP/report" >"$TMP/out" 2>"$TMP/err" || fail "compare exited $?: $(cat "$TMP/err")"
[[ $(grep -c "^reference " "$TMP/out") -eq 1 ]] || fail "expected one reference line: $(cat "$TMP/out")"
grep -q "^reference path, for every integrator: analytic spheres, 64 spp, rendered in" "$TMP/out" ||
  fail "the reference is not one path render: $(grep '^reference' "$TMP/out")"
[[ $(find "$TMP/cache" -name '*.exr' | wc -l) -eq 1 ]] || fail "not one cached reference"
widest=$(awk '{ if (length($0) > w) w = length($0) } END { print w }' <(sed -n '/^integrator/,/^wrote/p' "$TMP/out"))
if [[ $widest -le 100 ]]; then
  echo "ok: the table is $widest columns wide"
else
  fail "the table is $widest columns wide: $(cat "$TMP/out")"
fi

$PY - "$TMP/report" <<'EOF' || fail "results.json (see above)"
import json, os, sys
import numpy as np
import OpenImageIO as oiio
d = sys.argv[1]
r = json.load(open(os.path.join(d, "results.json")))
rows = r["rows"]
bad = []
refs = [x for x in rows if x["role"] == "reference"]
if [(x["integrator"], x["spp"]) for x in refs] != [("path", 64)]:
    bad.append("reference rows %s" % [(x["integrator"], x["spp"]) for x in refs])
tests = [x for x in rows if x["role"] == "test"]
if len(tests) != 3 * 2 * 4:
    bad.append("%d test rows, expected 24" % len(tests))
# Against the unbiased answer: the Cornell box is lit by its emissive ceiling alone, whose
# direct light whitted and shadow sample but whose indirect light (the walls lighting each
# other) they leave out, so their error stays well above path's.
def err(integ, spp, mode="analytic"):
    return next(x["relmse"] for x in tests if x["integrator"] == integ and x["spp"] == spp
                and x["sampling"] == "uniform" and x["spheres"] == mode)
if not err("path", 16) < err("path", 1):
    bad.append("path's error does not fall with spp: %s %s" % (err("path", 1), err("path", 16)))
# Path's error at 16 spp is its noise, (1/16 + 1/64) of a sample's variance against the
# reference's independent 64 samples (0.041 here); the biased integrators' is mostly what they
# leave out (0.120 here, 2.9 times path's), which more samples do not remove: from 4 to 16 spp
# noise alone would fall to a quarter (path's falls to 0.38 of itself), theirs keeps 0.92 of
# itself. (With a reference that shared path's samples, path's error read lower; compare.md.)
for biased in ("whitted", "shadow"):
    if not err(biased, 16) > 2 * err("path", 16):
        bad.append("%s's bias does not show: relMSE %s against path's %s" % (biased, err(biased, 16), err("path", 16)))
    if not err(biased, 16) > 0.75 * err(biased, 4):
        bad.append("%s's error falls with spp as noise would: %s at 4, %s at 16" % (biased, err(biased, 4), err(biased, 16)))
# Heat maps: one per test row, on the scale of the reference's mean.
ref = oiio.ImageBuf(os.path.join(d, "images", "path-reference.exr")).get_pixels(oiio.FLOAT)
mean = float(ref[..., :3].mean())
if abs(r["heatmap_peak"] - mean) > 1e-6 * mean:
    bad.append("heat map peak %s, the reference's mean is %s" % (r["heatmap_peak"], mean))
for x in tests:
    p = os.path.join(d, x["heatmap"])
    if not x["heatmap"].endswith("-error.png") or not os.path.isfile(p):
        bad.append("no heat map for %s %s %s: %r" % (x["integrator"], x["spheres"], x["spp"], x["heatmap"]))
        break
# Equal time: one row per integrator (the first sphere mode), the longest time all reached.
for key, field, pick in (("equal_time", "wall_seconds", max), ("equal_error", "relmse", min)):
    side = r[key]
    chosen = [rows[i] for i in side["rows"]]
    if sorted(c["integrator"] for c in chosen) != ["path", "shadow", "whitted"]:
        bad.append("%s rows are not one per integrator: %s" % (key, [c["integrator"] for c in chosen]))
    if any(c["spheres"] != "analytic" or c["role"] != "test" for c in chosen):
        bad.append("%s picked a row outside the first sphere mode's tests" % key)
    target = side["seconds" if key == "equal_time" else "error"]
    per = {}
    for x in tests:
        if x["spheres"] == "analytic":
            per.setdefault(x["integrator"], []).append(x[field])
    want = min(max(v) for v in per.values()) if key == "equal_time" else max(min(v) for v in per.values())
    if abs(target - want) > 1e-9 * want:
        bad.append("%s target %s, expected %s" % (key, target, want))
for b in bad:
    print("  " + b)
sys.exit(1 if bad else 0)
EOF

# The warm-ups: one untimed 1-spp render per BVH (two sphere modes here), not one per row.
warm=$($PY -c "import json,sys; print(json.load(open(sys.argv[1]))['warm_up_renders'])" "$TMP/report/results.json")
[[ $warm == 2 ]] && echo "ok: 2 warm-ups for 2 BVHs and 25 rows" || fail "$warm warm-up renders, expected 2"

# Second run: the path reference comes from the cache; --reference-integrator self renders each
# integrator's own; a name that is not an integrator is a usage error.
"$PRISM" "${ARGS[@]}" -o "$TMP/report2" >"$TMP/out2" 2>&1 || fail "second compare exited $?"
grep -q "^reference path, for every integrator: .*from the cache" "$TMP/out2" ||
  fail "second run did not take the path reference from the cache: $(grep '^reference' "$TMP/out2")"
"$PRISM" compare "$SCENE" --res 16x16 --spp 1 --integrators whitted,shadow --reference-spp 4 \
  --reference-integrator self -o "$TMP/self" >"$TMP/out3" 2>&1 || fail "self compare exited $?"
[[ $(grep -c "^reference \(whitted\|shadow\): analytic spheres, 4 spp" "$TMP/out3") -eq 2 ]] ||
  fail "--reference-integrator self did not render each integrator's own: $(grep '^reference' "$TMP/out3")"
expect 2 "^prism: error: --reference-integrator pathh: expected phong, shadow, whitted or path$" -- compare "$SCENE" \
  --res 16x16 --spp 1 --reference-integrator pathh -o "$TMP/bad"
[[ -e "$TMP/bad" ]] && fail "a refused compare created its report directory"

echo "$failures failed"
[[ $failures -eq 0 ]]
