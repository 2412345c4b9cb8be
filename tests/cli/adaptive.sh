#!/usr/bin/env bash
# Adaptive sampling from the command line: --target-error, --time-limit, --min-spp and
# --sample-count-image; their metadata and summary; absurd values refused in one line with
# nothing written. Usage: adaptive.sh PRISM SOURCE_DIR
source "$(dirname "$0")/lib/common.bash" "$@"
SCENE="$SRC/scenes/spheres.gltf"

# expect_usage PATTERN ARGS...: exit code 2, one line on stderr matching PATTERN, no output.
expect_usage() {
  local pattern=$1
  shift
  rm -f "$TMP/bad.exr"
  "$PRISM" render "$SCENE" -o "$TMP/bad.exr" --res 32x18 "$@" >"$TMP/out" 2>"$TMP/err"
  local got=$?
  if [[ $got -ne 2 ]]; then
    fail "$* exited $got, expected 2: $(cat "$TMP/err")"
  elif [[ $(wc -l <"$TMP/err") -ne 1 ]]; then
    fail "$* printed $(wc -l <"$TMP/err") lines on stderr: $(cat "$TMP/err")"
  elif ! grep -qE -- "$pattern" "$TMP/err"; then
    fail "$*: stderr does not match '$pattern': $(cat "$TMP/err")"
  elif [[ -e "$TMP/bad.exr" ]]; then
    fail "$*: wrote an image anyway"
  else
    echo "ok: $* -> $(cat "$TMP/err")"
  fi
}

expect_usage "--target-error" --target-error -0.1
expect_usage "--target-error" --target-error 0
expect_usage "--target-error" --target-error nan
expect_usage "--time-limit" --time-limit 0
expect_usage "--time-limit" --time-limit -5
expect_usage "--min-spp" --min-spp 0
expect_usage "--min-spp 12: must be a power of two" --min-spp 12 --target-error 0.01
# A maximum at or below the minimum leaves adaptive sampling nothing to decide.
expect_usage "--target-error 0.01 with --spp 8: adaptive sampling takes --min-spp 8 samples .*raise --spp above 8" \
  --target-error 0.01 --spp 8
expect_usage "--target-error 0.05 with --spp 1: .*--min-spp 8" --target-error 0.05 --spp 1
expect_usage "--target-error 0.05 with --spp 4: .*--min-spp 4 samples" --target-error 0.05 --spp 4 --min-spp 4
expect_usage "--error-goal frame: expected pixel or image" --error-goal frame --target-error 0.01
expect_usage "--error-goal image: bounds a --target-error, and none is set" --error-goal image
expect_usage "--sample-count-image .*must end in .exr" --target-error 0.01 \
  --sample-count-image "$TMP/counts.png"

# A target error: fewer samples than the maximum, recorded in the summary and the EXR, the
# same pixels and counts with 1 and 2 threads.
for threads in 1 2; do
  "$PRISM" render "$SCENE" -o "$TMP/a$threads.exr" --res 160x90 --spp 64 --target-error 0.02 \
    --threads "$threads" --sample-count-image "$TMP/n$threads.exr" >"$TMP/stdout" 2>"$TMP/stderr" ||
    fail "adaptive render with $threads threads: $(cat "$TMP/stderr")"
done
grep -qE "^rendered .* 64 spp max, [0-9.]+ mean, [0-9]+ rounds," "$TMP/stdout" ||
  fail "summary lacks the mean spp: $(head -1 "$TMP/stdout")"
grep -q "^wrote .*n2.exr" "$TMP/stdout" || fail "summary lacks the sample-count image"
idiff -fail 0 -failpercent 0 -warn 0 "$TMP/a1.exr" "$TMP/a2.exr" >/dev/null || fail "1 and 2 threads differ"
idiff -fail 0 -failpercent 0 -warn 0 "$TMP/n1.exr" "$TMP/n2.exr" >/dev/null || fail "sample counts differ"
info=$(iinfo -v "$TMP/a1.exr")
for expected in "prism:spp: 64" 'prism:adaptiveTargetError: "0.02"' 'prism:adaptiveMinSpp: "8"' \
  'prism:adaptiveErrorGoal: "pixel"' \
  'prism:adaptiveRounds: "' 'prism:samplesTaken: "' 'prism:meanSpp: "'; do
  grep -qF "$expected" <<<"$info" || fail "EXR lacks '$expected'"
done
# The counts lie between the minimum and the maximum, and are not all the maximum.
stats=$(oiiotool "$TMP/n1.exr" --printstats 2>&1)
grep -qE "Min: 8\.0+ " <<<"$stats" || fail "smallest sample count is not 8: $(grep Min: <<<"$stats")"
grep -qE "Max: 64\.0+ " <<<"$stats" || fail "largest sample count is not 64: $(grep Max: <<<"$stats")"

# The image goal: fewer samples than every pixel below the same target takes, the same
# pixels with 1 and 2 threads, said in the EXR.
for threads in 1 2; do
  "$PRISM" render "$SCENE" -o "$TMP/g$threads.exr" --res 160x90 --spp 64 --target-error 0.02 \
    --error-goal image --threads "$threads" >"$TMP/stdout$threads" 2>"$TMP/stderr" ||
    fail "image-goal render with $threads threads: $(cat "$TMP/stderr")"
done
idiff -fail 0 -failpercent 0 -warn 0 "$TMP/g1.exr" "$TMP/g2.exr" >/dev/null ||
  fail "image goal: 1 and 2 threads differ"
iinfo -v "$TMP/g1.exr" | grep -qF 'prism:adaptiveErrorGoal: "image"' || fail "EXR lacks the image goal"
mean_spp() { iinfo -v "$1" | sed -n 's/.*prism:meanSpp: "\([0-9.]*\)".*/\1/p'; }
pixel_spp=$(mean_spp "$TMP/a1.exr")
image_spp=$(mean_spp "$TMP/g1.exr")
awk -v a="$image_spp" -v b="$pixel_spp" 'BEGIN { exit !(a < b) }' ||
  fail "image goal took $image_spp spp mean, the pixel goal $pixel_spp"
echo "ok: target 0.02: image goal $image_spp spp mean, pixel goal $pixel_spp"

# A time limit that passes during the first round: one round of --min-spp samples, said so.
"$PRISM" render "$SCENE" -o "$TMP/t.exr" --res 160x90 --spp 256 --min-spp 4 --time-limit 0.000001 \
  >"$TMP/stdout" 2>"$TMP/stderr" || fail "time-limited render: $(cat "$TMP/stderr")"
grep -q "time limit reached" "$TMP/stdout" || fail "summary does not say the time limit was reached"
grep -q "^prism: --time-limit .* reached after round 1 " "$TMP/stderr" ||
  fail "stderr does not report the time limit: $(cat "$TMP/stderr")"
grep -q "^rays .*camera 57,600," "$TMP/stdout" || fail "not one round of 4 spp: $(grep ^rays "$TMP/stdout")"
iinfo -v "$TMP/t.exr" | grep -qF 'prism:adaptiveTimeLimitReached: "1"' || fail "EXR lacks the time-limit flag"

# Without the flags: the uniform render, no adaptive metadata.
"$PRISM" render "$SCENE" -o "$TMP/u.exr" --res 160x90 --spp 4 --quiet || fail "uniform render"
iinfo -v "$TMP/u.exr" | grep -q "adaptive" && fail "uniform render has adaptive metadata"

echo "$failures failed"
[[ $failures -eq 0 ]]
