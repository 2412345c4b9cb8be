#!/usr/bin/env bash
# `prism compare`'s rendered reference draws its own sample stream (RenderSettings::seed), so
# a render's error against it holds the render's whole noise. With the renders' own stream,
# path at N spp against a path reference of M spp would share the first N samples: at N = M
# the two images were identical (relMSE 0), and below it the error was (1/N - 1/M) of the
# variance instead of (1/N + 1/M). Here, with v the variance of one 64-spp render: against a
# 64-spp reference the error is about 2 v, against a 256-spp one about 1.25 v, a ratio of 1.6
# (shared samples: 0 and 0.75 v). With --seed 1 the renders draw the stream references use
# by default, so the reference takes another: its error is again about 2 v, not 0, and a
# draw of its own. Usage: compare_independent_reference.sh PRISM SOURCE_DIR
source "$(dirname "$0")/lib/common.bash" "$@"
SCENE="$SRC/scenes/cornell.gltf"
export XDG_CACHE_HOME="$TMP/cache"
for run in "64 0" "256 0" "64 1"; do
  read -r m seed <<<"$run"
  "$PRISM" compare "$SCENE" --res 48x48 --spp 64 --integrators path --spheres analytic \
    --reference-spp $m --seed $seed --threads 2 -o "$TMP/report$m-$seed" >"$TMP/out" 2>"$TMP/err" ||
    fail "compare --reference-spp $m --seed $seed exited $?: $(cat "$TMP/err")"
done
/usr/bin/python3 - "$TMP/report64-0" "$TMP/report256-0" "$TMP/report64-1" <<'PY' ||
import json, sys
def relmse(d):
    rows = json.load(open(d + "/results.json"))["rows"]
    return next(x["relmse"] for x in rows if x["role"] == "test" and x["integrator"] == "path")
r64, r256, seeded = (relmse(d) for d in sys.argv[1:])
print("path 64 spp: relMSE %.6g against a 64-spp reference, %.6g against 256 spp: ratio %.3f "
      "(independent: about 1.6; shared samples: 0)" % (r64, r256, r64 / r256))
print("with --seed 1: %.6g against a 64-spp reference, %.3f of seed 0's (about 1; shared: 0)"
      % (seeded, seeded / r64))
sys.exit(0 if r64 > 0 and 1.2 < r64 / r256 < 2.0 and seeded != r64 and 0.7 < seeded / r64 < 1.4
         else 1)
PY
  fail "the errors (above)"
echo "$failures failed"
[[ $failures -eq 0 ]]
