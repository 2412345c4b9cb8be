#!/usr/bin/env bash
# `prism compare`: the report's rows and their values, the CSV, the images and plots, the
# reference cache, and index.html as Chromium draws it. Usage: compare.sh PRISM SOURCE_DIR
source "$(dirname "$0")/lib/common.bash" "$@"
SCENE="$SRC/scenes/spheres.gltf"
PY=/usr/bin/python3
# The references are cached here, not in the user's ~/.cache.
export XDG_CACHE_HOME="$TMP/cache"
ARGS=(compare "$SCENE" --res 64x36 --spp 1,4 --integrators phong,whitted --reference-integrator self
  --spheres analytic,mesh:2 --reference-spp 16 --threads 2)

"$PRISM" "${ARGS[@]}" -o "$TMP/report" >"$TMP/out1" 2>"$TMP/err1" || fail "compare exited $?"
cat "$TMP/out1"
[[ -s "$TMP/err1" ]] && fail "stderr not empty: $(cat "$TMP/err1")"
[[ $(grep -c "^reference .*rendered in .* cached as $TMP/cache/prism/references/[0-9a-f]\{32\}\.exr" \
  "$TMP/out1") -eq 2 ]] || fail "first run: the two references were not rendered and cached"
ls "$TMP"/cache/prism/references/*.exr >/dev/null 2>&1 || fail "nothing in the cache"

# Every row's values, checked against what they must be.
$PY - "$TMP/report" <<'PYEOF' || fail "results.json (see above)"
import csv, json, math, os, sys
d = sys.argv[1]
doc = json.load(open(os.path.join(d, "results.json")))
rows = doc["rows"]
bad = []
def check(cond, what):
    if not cond: bad.append(what)
W, H = 64, 36
check(doc["width"] == W and doc["height"] == H, "size %sx%s" % (doc["width"], doc["height"]))
check(len(rows) == 2 + 2 * 2 * 2, "%d rows, expected 10" % len(rows))
refs = [r for r in rows if r["role"] == "reference"]
tests = [r for r in rows if r["role"] == "test"]
check([r["integrator"] for r in refs] == ["phong", "whitted"], "reference rows first")
for r in refs:
    check(r["spheres"] == "analytic" and r["spp"] == 16, "reference settings %s" % r)
    check(r["source"] == "rendered", "reference source %s" % r["source"])
    check(r["rays_camera"] == W * H * 16, "reference camera rays %d" % r["rays_camera"])
    check(r["wall_seconds"] > 0 and r["bvh_build_seconds"] > 0, "reference times")
    check(r["rmse"] is None, "a reference has no error")
combos = {(r["integrator"], r["spheres"], r["spp"]) for r in tests}
check(combos == {(i, s, n) for i in ("phong", "whitted") for s in ("analytic", "mesh:2") for n in (1, 4)},
      "combinations %s" % sorted(combos))
for r in tests:
    name = "%s %s %d" % (r["integrator"], r["spheres"], r["spp"])
    check(r["rays_camera"] == W * H * r["spp"], name + ": camera rays %d" % r["rays_camera"])
    total = r["rays_camera"] + r["rays_shadow"] + r["rays_reflection"] + r["rays_refraction"]
    check(r["wall_seconds"] > 0 and r["bvh_build_seconds"] > 0, name + ": times")
    check(abs(r["rays_per_second"] - total / r["wall_seconds"]) <= 1e-6 * r["rays_per_second"],
          name + ": rays/s is not rays / seconds")
    if r["integrator"] == "phong":
        check(r["rays_shadow"] == 0 and r["rays_reflection"] == 0, name + ": phong casts only camera rays")
    else:
        check(r["rays_shadow"] > 0 and r["rays_reflection"] > 0 and r["rays_refraction"] > 0,
              name + ": whitted casts shadow, reflection and refraction rays")
    check(0 < r["rmse"] < 1 and 0 < r["relmse"] < 1, name + ": rmse %s relmse %s" % (r["rmse"], r["relmse"]))
    check(abs(r["psnr_db"] + 10 * math.log10(r["rmse"] ** 2)) < 1e-9, name + ": PSNR is not 10 log10(1/MSE)")
    check(10 < r["peak_rss_mib"] < 100000, name + ": peak RSS %s MiB" % r["peak_rss_mib"])
    check(os.path.isfile(os.path.join(d, r["image"])), name + ": no " + r["image"])
    check(os.path.isfile(os.path.join(d, r["image"][:-4] + ".exr")), name + ": no EXR")
for i in ("phong", "whitted"):
    for s in ("analytic", "mesh:2"):
        e = {r["spp"]: r["rmse"] for r in tests if r["integrator"] == i and r["spheres"] == s}
        check(e[4] < e[1], "%s %s: RMSE does not fall from 1 to 4 spp: %s" % (i, s, e))
check(any(r["pareto"] for r in tests), "no point on the Pareto front")
check(not any(r["pareto"] for r in refs), "a reference on the Pareto front")
with open(os.path.join(d, "results.csv")) as f:
    table = list(csv.DictReader(f))
check(len(table) == len(rows), "CSV has %d rows, JSON %d" % (len(table), len(rows)))
for c, j in zip(table, rows):
    check(c["integrator"] == j["integrator"] and c["spheres"] == j["spheres"] and int(c["spp"]) == j["spp"],
          "CSV row %s differs from JSON %s" % (c, j))
    check(int(c["rays_shadow"]) == j["rays_shadow"], "CSV shadow rays differ")
    check((c["rmse"] == "" and j["rmse"] is None) or float(c["rmse"]) == j["rmse"], "CSV rmse differs")
for b in bad: print("  " + b)
sys.exit(1 if bad else 0)
PYEOF

iinfo "$TMP/report/images/whitted-mesh2-4spp.png" | grep -qF "64 x   36, 3 channel, uint8 png" ||
  fail "image PNG: $(iinfo "$TMP/report/images/whitted-mesh2-4spp.png")"
iinfo "$TMP/report/images/phong-reference.exr" | grep -qF "64 x   36, 4 channel, float openexr" ||
  fail "reference EXR: $(iinfo "$TMP/report/images/phong-reference.exr")"
iinfo "$TMP/report/plot.png" | grep -qF "800 x  500, 3 channel, uint8 png" ||
  fail "plot.png: $(iinfo "$TMP/report/plot.png")"
$PY - "$TMP/report/plot.svg" <<'PYEOF' || fail "plot.svg"
import sys, xml.etree.ElementTree as ET
root = ET.parse(sys.argv[1]).getroot()
texts = [t.text for t in root.iter("{http://www.w3.org/2000/svg}text")]
want = ["phong, analytic", "phong, mesh:2", "whitted, analytic", "whitted, mesh:2", "Pareto front"]
missing = [w for w in want if w not in texts]
if root.get("width") != "800" or missing:
    print("  svg width %s, legend lacks %s" % (root.get("width"), missing)); sys.exit(1)
PYEOF

# Second run: both references come from the cache, and the renders are the same pixels.
"$PRISM" "${ARGS[@]}" -o "$TMP/again" >"$TMP/out2" 2>&1 || fail "second compare exited $?"
[[ $(grep -c "^reference .*from the cache" "$TMP/out2") -eq 2 ]] ||
  fail "second run did not take both references from the cache: $(cat "$TMP/out2")"
$PY - "$TMP/report/results.json" "$TMP/again/results.json" <<'PYEOF' || fail "second run's rows"
import json, sys
a, b = (json.load(open(p))["rows"] for p in sys.argv[1:])
bad = [(x["integrator"], x["spheres"], x["spp"]) for x, y in zip(a, b) if x["rmse"] != y["rmse"]]
src = [y["source"] for y in b if y["role"] == "reference"]
if bad or src != ["cache", "cache"] or len(a) != len(b):
    print("  errors differ for %s; reference sources %s" % (bad, src)); sys.exit(1)
PYEOF

# Bad input: one line naming the option, exit 2, no report written.
"$PRISM" "${ARGS[@]}" -o "$TMP/bad" --spp 1,1 2>"$TMP/err" >/dev/null
code=$?
{ [[ $code -eq 2 && $(wc -l <"$TMP/err") -eq 1 ]] && grep -q -- "--spp 1: given twice" "$TMP/err"; } ||
  fail "duplicate spp: exit $code, $(cat "$TMP/err")"
"$PRISM" compare "$SCENE" --res 32x18 --reference "$TMP/report/images/phong-reference.exr" \
  -o "$TMP/bad" 2>"$TMP/err" >/dev/null
code=$?
{ [[ $code -eq 2 ]] && grep -q -- "--reference .*is 64x36 but the render is 32x18" "$TMP/err"; } ||
  fail "reference of another size: exit $code, $(cat "$TMP/err")"
[[ -e "$TMP/bad" ]] && fail "a refused compare created its report directory"

# index.html as a browser shows it. scripts/setup.sh installs Chromium for this.
CHROMIUM=$(command -v chromium || command -v chromium-browser || true)
if [[ -z $CHROMIUM ]]; then
  fail "chromium not found: run scripts/setup.sh"
else
  chrome() {
    "$CHROMIUM" --headless --no-sandbox --disable-gpu --disable-quic --no-first-run \
      --disable-background-networking --disable-component-update --disable-sync \
      --user-data-dir="$(mktemp -d -p "$TMP")" --window-size=1400,1000 "$@" \
      "file://$TMP/report/index.html" 2>/dev/null
  }
  chrome --dump-dom >"$TMP/dom.html"
  $PY - "$TMP/dom.html" <<'PYEOF' || fail "index.html's DOM"
import sys
from html.parser import HTMLParser
class P(HTMLParser):
    def __init__(self):
        super().__init__(); self.imgs = []; self.rows = 0
    def handle_starttag(self, tag, attrs):
        if tag == "img": self.imgs.append(dict(attrs)["src"])
        if tag == "tr": self.rows += 1
p = P(); p.feed(open(sys.argv[1]).read())
bad = []
if p.imgs.count("plot.svg") != 1: bad.append("plot.svg shown %d times" % p.imgs.count("plot.svg"))
images = [i for i in p.imgs if i != "plot.svg"]
# Ten renders, then equal time and equal error: per integrator an image above its heat map.
shown, sides = images[:10], images[10:]
if len(shown) != 10 or len(set(shown)) != 10: bad.append("%d images: %s" % (len(shown), shown))
if len(sides) != 8 or any(sides[i + 1] != sides[i][:-4] + "-error.png" for i in range(0, len(sides), 2)):
    bad.append("side-by-side images: %s" % sides)
if sorted(s.split("/")[1].split("-")[0] for s in sides[0:4:2]) != ["phong", "whitted"]:
    bad.append("equal time does not show both integrators: %s" % sides[0:4])
if images and images[0] != "images/phong-reference.png": bad.append("first image " + images[0])
if p.rows != 11: bad.append("%d table rows, expected a header and 10" % p.rows)
for b in bad: print("  " + b)
sys.exit(1 if bad else 0)
PYEOF
  chrome --screenshot="$TMP/page.png"
  # A page that failed to draw is white; this one has photos, a plot and a table.
  stddev=$(oiiotool "$TMP/page.png" --printstats 2>/dev/null | awk '/Stats StdDev/ {print $3}')
  $PY -c "import sys; sys.exit(0 if float('${stddev:-0}') > 10 else 1)" ||
    fail "screenshot looks blank (standard deviation ${stddev:-none} of 255)"
fi

echo "$failures failed"
[[ $failures -eq 0 ]]
