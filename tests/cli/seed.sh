#!/usr/bin/env bash
# `prism render --seed N`: seed 0 is the default render bit for bit; another seed is the same
# image in expectation with independent noise (the difference between two seeds' renders has
# the variance of both renders' noise, not 0), bit-identical whatever the thread count,
# recorded in the EXR (prism:sampleSeed) and in the checkpoint's job, so a checkpoint of one
# seed never continues a render of another; a bad seed is a one-line usage error.
# Usage: seed.sh PRISM SOURCE_DIR
source "$(dirname "$0")/lib/common.bash" "$@"
SCENE="$SRC/scenes/cornell.gltf"
PY=/usr/bin/python3
ARGS=(--integrator path --spp 16 --res 64x64 --quiet)

"$PRISM" render "$SCENE" -o "$TMP/default.exr" "${ARGS[@]}" --threads 2 || fail "default render"
"$PRISM" render "$SCENE" -o "$TMP/s0.exr" "${ARGS[@]}" --threads 2 --seed 0 || fail "seed 0"
"$PRISM" render "$SCENE" -o "$TMP/s7.exr" "${ARGS[@]}" --threads 2 --seed 7 || fail "seed 7"
"$PRISM" render "$SCENE" -o "$TMP/s7b.exr" "${ARGS[@]}" --threads 1 --seed 7 ||
  fail "seed 7, one thread"
"$PRISM" render "$SCENE" -o "$TMP/s9.exr" "${ARGS[@]}" --threads 2 --seed 9 || fail "seed 9"
for seed in 3 5; do
  "$PRISM" render "$SCENE" -o "$TMP/ref$seed.exr" --integrator path --spp 256 --res 64x64 \
    --quiet --threads 2 --seed $seed || fail "reference of seed $seed"
done

# What the images must show, in numbers: default == seed 0 and seed 7 on 2 threads == seed 7
# on 1 thread, exactly; seeds 0, 7 and 9 differ in most pixels (not those that see only the
# light or nothing); their noise is independent and their image means agree within it.
"$PY" - "$TMP" <<'PYEOF' || fail "seeds' images"
import sys
import numpy as np
import OpenImageIO as oiio
d = sys.argv[1]
img = {n: oiio.ImageBuf("%s/%s.exr" % (d, n)).get_pixels(oiio.FLOAT)[..., :3].astype(np.float64)
       for n in ("default", "s0", "s7", "s7b", "s9")}
errors = []
if not np.array_equal(img["default"], img["s0"]):
    errors.append("--seed 0 is not the default render")
if not np.array_equal(img["s7"], img["s7b"]):
    errors.append("seed 7 differs between 2 threads and 1 thread")
for a, b in (("s0", "s7"), ("s0", "s9"), ("s7", "s9")):
    share = float(np.mean(np.any(img[a] != img[b], axis=-1)))
    print("%s vs %s: %.3f of pixels differ" % (a, b, share))
    if share < 0.9:
        errors.append("%s and %s differ in only %.3f of the pixels" % (a, b, share))
# Independent noise: one render's error against a 256-spp reference of seed 3 is uncorrelated
# with the other's against seed 5's when all four streams are independent (a shared stream
# would correlate them almost fully: 0.84 for seed 0 against the default render). Rank
# correlation (Spearman's), because a path-traced error is heavy-tailed: a few bright paths
# decide Pearson's coefficient (-0.16 and +0.09 here). Pooled over pixels whose errors are
# skewed by different amounts it is not exactly 0 for independent renders either (their
# medians sit below 0 together where a pixel's light comes from rare paths): 0.033 and 0.038
# at 16 spp, hence the bound of 0.1.
ref3, ref5 = (oiio.ImageBuf("%s/ref%d.exr" % (d, k)).get_pixels(oiio.FLOAT)[..., :3]
              .astype(np.float64) for k in (3, 5))
ref = 0.5 * (ref3 + ref5)
for a, b in (("s0", "s7"), ("s7", "s9"), ("s0", "default")):
    ea, eb = (img[a] - ref3).ravel(), (img[b] - ref5).ravel()
    keep = (ea != 0) | (eb != 0)  # pixels with noise (not the light, not the black outside)
    ranks = [np.argsort(np.argsort(e[keep])) for e in (ea, eb)]
    corr = float(np.corrcoef(ranks[0], ranks[1])[0, 1])
    print("errors of %s and %s against the reference: rank correlation %.4f over %d values"
          % (a, b, corr, keep.sum()))
    shared = b == "default"  # the control: the same stream, which the test must tell apart
    if (corr < 0.5) if shared else (abs(corr) > 0.1):
        errors.append("%s and %s: rank correlation %.4f" % (a, b, corr))
means = np.array([img[n].mean() for n in ("s0", "s7", "s9")])
sd = float(np.sqrt(np.mean((img["s0"] - ref) ** 2) / ref.size))
print("image means %s, sd of one image's mean %.5f" % (np.round(means, 5), sd))
if np.ptp(means) > 5.0 * sd:
    errors.append("image means %s differ by more than 5 sd (%.5f)" % (means, sd))
if errors:
    print("; ".join(errors))
    sys.exit(1)
PYEOF

"$PY" - "$TMP/s7.exr" "$TMP/s0.exr" <<'PYEOF' || fail "sampleSeed metadata"
import sys
import OpenImageIO as oiio
seeded = oiio.ImageInput.open(sys.argv[1]).spec().get_string_attribute("prism:sampleSeed")
default = oiio.ImageInput.open(sys.argv[2]).spec().get_string_attribute("prism:sampleSeed")
print("prism:sampleSeed %r (seed 7), %r (seed 0)" % (seeded, default))
sys.exit(0 if seeded == "7" and default == "" else 1)
PYEOF

# A checkpoint written for seed 7 is not continued by a render of seed 0: SIGTERM stops a
# checkpointing render, and the re-run with another seed renders from zero, equal to the
# uninterrupted seed-0 render.
"$PRISM" render "$SCENE" -o "$TMP/ck.exr" --integrator path --spp 4096 --res 64x64 --quiet \
  --threads 2 --seed 7 --checkpoint-interval 1000 &
pid=$!
for _ in $(seq 1 50); do sleep 0.1; done
kill -TERM "$pid" 2>/dev/null
wait "$pid"
code=$?
if [[ $code -ne 143 || ! -f "$TMP/ck.exr.checkpoint" ]]; then
  fail "SIGTERM of the seed-7 render: exit $code, checkpoint $(ls "$TMP" | tr '\n' ' ')"
else
  "$PRISM" render "$SCENE" -o "$TMP/ck.exr" "${ARGS[@]}" --threads 2 --seed 0 \
    --checkpoint-interval 1000 || fail "seed-0 re-run beside seed 7's checkpoint"
  if "$PRISM" diff "$TMP/ck.exr" "$TMP/s0.exr" --metric max --fail-above 0 >"$TMP/diff" 2>&1; then
    echo "ok: the seed-0 re-run ignored seed 7's checkpoint ($(tail -1 "$TMP/diff"))"
  else
    fail "seed-0 re-run differs from the uninterrupted seed-0 render: $(cat "$TMP/diff")"
  fi
fi

expect 2 "--seed.*whole number from 0 to 2147483647, not -1" -- render "$SCENE" -o "$TMP/x.exr" --seed -1
expect 2 "--seed.*not 4294967296" -- render "$SCENE" -o "$TMP/x.exr" --seed 4294967296
expect 2 "--seed.*not abc" -- render "$SCENE" -o "$TMP/x.exr" --seed abc
[[ -e "$TMP/x.exr" ]] && fail "a refused seed wrote $TMP/x.exr"

echo "$failures failed"
[[ $failures -eq 0 ]]
