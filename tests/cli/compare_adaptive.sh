#!/usr/bin/env bash
# `prism compare --target-errors`: adaptive rows next to the uniform ones, their sampling and
# mean spp in every output, on the plot and its Pareto front; bad values refused as `prism
# render` refuses them. Usage: compare_adaptive.sh PRISM SOURCE_DIR
source "$(dirname "$0")/lib/common.bash" "$@"
SCENE="$SRC/scenes/spheres.gltf"
PY=/usr/bin/python3
export XDG_CACHE_HOME="$TMP/cache"
# A reference of 1024 spp, its own sample stream: an error measured against it is the row's
# own, not the reference's noise, which at 64 spp was as large as the adaptive rows' and
# hid which of them had less.
ARGS=(compare "$SCENE" --res 64x36 --spp 1,32 --integrators whitted --reference-integrator self --reference-spp 1024
  --threads 2)

"$PRISM" "${ARGS[@]}" --target-errors 0.1,0.05 --min-spp 4 -o "$TMP/report" >"$TMP/out" \
  2>"$TMP/err" || fail "compare exited $?: $(cat "$TMP/err")"
cat "$TMP/out"
[[ -s "$TMP/err" ]] && fail "stderr not empty: $(cat "$TMP/err")"
for e in 0.1 0.05; do
  grep -qE "^whitted +adaptive $e +32 " "$TMP/out" || fail "no 'adaptive $e' row in the table"
done

$PY - "$TMP/report" <<'PYEOF' || fail "results (see above)"
import csv, json, math, os, sys
d = sys.argv[1]
doc = json.load(open(os.path.join(d, "results.json")))
rows = doc["rows"]
bad = []
def check(cond, what):
    if not cond: bad.append(what)
W, H, MIN, CAP = 64, 36, 4, 32
check(doc["adaptive_min_spp"] == MIN, "adaptive_min_spp %s" % doc["adaptive_min_spp"])
check(len(rows) == 1 + 2 + 2, "%d rows, expected 5" % len(rows))
check([(r["role"], r["sampling"], r["target_error"], r["spp"]) for r in rows] ==
      [("reference", "uniform", None, 1024), ("test", "uniform", None, 1), ("test", "uniform", None, 32),
       ("test", "adaptive", 0.1, CAP), ("test", "adaptive", 0.05, CAP)],
      "row order and sampling: %s" % [(r["sampling"], r["target_error"], r["spp"]) for r in rows])
for r in rows:
    check(r["mean_spp"] == r["rays_camera"] / (W * H), "%s: mean spp is not camera rays / pixels" % r)
uniform = {r["spp"]: r for r in rows if r["role"] == "test" and r["sampling"] == "uniform"}
adaptive = {r["target_error"]: r for r in rows if r["sampling"] == "adaptive"}
for n, r in uniform.items():
    check(r["mean_spp"] == n, "uniform %d spp: mean spp %s" % (n, r["mean_spp"]))
for e, r in adaptive.items():
    name = "adaptive %g" % e
    print("  %s: mean spp %.3f, rmse %.5g, relmse %.5g (1 spp: rmse %.5g, relmse %.5g)" % (
        name, r["mean_spp"], r["rmse"], r["relmse"], uniform[1]["rmse"], uniform[1]["relmse"]))
    check(MIN < r["mean_spp"] < CAP, name + ": mean spp %s not strictly between %d and %d" % (r["mean_spp"], MIN, CAP))
    check(all(math.isfinite(r[k]) for k in ("rmse", "relmse", "psnr_db")), name + ": non-finite error")
    check(r["rmse"] < uniform[1]["rmse"] and r["relmse"] < uniform[1]["relmse"],
          name + ": error not below the 1-spp uniform row's")
    check(r["rays_shadow"] > 0 and r["rays_reflection"] > 0, name + ": whitted's secondary rays")
    check(os.path.isfile(os.path.join(d, r["image"])), name + ": no " + r["image"])
# A lower target takes more samples for a lower error.
check(adaptive[0.05]["mean_spp"] > adaptive[0.1]["mean_spp"] and adaptive[0.05]["relmse"] < adaptive[0.1]["relmse"],
      "target 0.05 is not more samples and less error than 0.1")
# The Pareto front is over every test row, adaptive ones too (relMSE, the default metric).
tests = [r for r in rows if r["role"] == "test"]
for p in tests:
    beaten = any(q["wall_seconds"] <= p["wall_seconds"] and q["relmse"] <= p["relmse"] and
                 (q["wall_seconds"] < p["wall_seconds"] or q["relmse"] < p["relmse"]) for q in tests)
    check(p["pareto"] == (not beaten), "%s %s: pareto %s" % (p["sampling"], p["target_error"], p["pareto"]))
with open(os.path.join(d, "results.csv")) as f:
    table = list(csv.DictReader(f))
check(len(table) == len(rows), "CSV has %d rows" % len(table))
for c, j in zip(table, rows):
    check(c["sampling"] == j["sampling"] and float(c["mean_spp"]) == j["mean_spp"] and
          ((c["target_error"] == "" and j["target_error"] is None) or float(c["target_error"]) == j["target_error"]),
          "CSV row differs from JSON: %s" % c)
for b in bad: print("  " + b)
sys.exit(1 if bad else 0)
PYEOF

# The adaptive EXR records its sampling as `prism render` does.
meta=$(iinfo -v "$TMP/report/images/whitted-analytic-adaptive005-32spp.exr")
for key in 'prism:adaptiveTargetError: "0.05"' 'prism:adaptiveMinSpp: "4"' 'prism:meanSpp'; do
  grep -qF "$key" <<<"$meta" || fail "adaptive EXR lacks $key"
done
# The plot: two adaptive diamonds and the legend's, labelled by target error.
$PY - "$TMP/report/plot.svg" <<'PYEOF' || fail "plot.svg"
import sys, xml.etree.ElementTree as ET
root = ET.parse(sys.argv[1]).getroot()
ns = "{http://www.w3.org/2000/svg}"
texts = [t.text for t in root.iter(ns + "text")]
diamonds = len(list(root.iter(ns + "polygon")))
missing = [w for w in ("e 0.1", "e 0.05", "adaptive, e target error") if w not in texts]
if diamonds != 3 or missing:
    print("  %d diamonds, expected 3; labels missing: %s" % (diamonds, missing)); sys.exit(1)
PYEOF
for caption in "whitted, analytic, 32 spp max, adaptive 0.1, " "<td class=\"name\">adaptive 0.05</td>"; do
  grep -qF "$caption" "$TMP/report/index.html" || fail "index.html lacks '$caption'"
done

# Bad values: one line naming the option as `prism render` does, exit 2, nothing written.
expect_usage() {
  local pattern=$1
  shift
  "$PRISM" "${ARGS[@]}" -o "$TMP/bad" "$@" >"$TMP/out" 2>"$TMP/err"
  local got=$?
  if [[ $got -ne 2 || $(wc -l <"$TMP/err") -ne 1 ]] || ! grep -qE -- "$pattern" "$TMP/err"; then
    fail "$*: exit $got, expected 2 and one line matching '$pattern': $(cat "$TMP/err")"
  elif [[ -e "$TMP/bad" ]]; then
    fail "$*: created the report directory anyway"
  else
    echo "ok: $* -> $(cat "$TMP/err")"
  fi
}
expect_usage "--target-error: must be a finite number > 0, not 0 \(see" --target-errors 0.1,0
expect_usage "--target-error: must be a finite number > 0, not -0.1" --target-errors -0.1
expect_usage "--target-error: must be a finite number > 0, not nan" --target-errors nan
expect_usage "--target-error 0.1: given twice" --target-errors 0.1,0.10
expect_usage "--min-spp 12: must be a power of two" --target-errors 0.1 --min-spp 12
expect_usage "--min-spp" --target-errors 0.1 --min-spp 0
expect_usage "--min-spp requires --target-error" --min-spp 4

echo "$failures failed"
[[ $failures -eq 0 ]]
