#!/usr/bin/env bash
# Checkpoints from the command line: --checkpoint-interval saves OUT.exr.checkpoint while
# rendering; SIGTERM or SIGUSR1 saves and stops (143 or 138, no image); SIGINT stops with
# nothing saved or written (130); a re-run resumes and writes the same pixels as an
# uninterrupted render, also after a kill -9; a changed option renders from the start.
# Usage: checkpoint.sh PRISM SOURCE_DIR
source "$(dirname "$0")/lib/common.bash" "$@"
SCENE="$SRC/scenes/spheres.gltf"
# A few seconds on one thread, so that signals arrive mid-render.
SPP=512
FILM=(--res 160x90 --spp "$SPP" --threads 1)
OUT="$TMP/out.exr"
CKPT="$OUT.checkpoint"
RUN=(render "$SCENE" -o "$OUT" "${FILM[@]}" --checkpoint-interval 1)

# wait_for FILE: true once FILE exists, false after 30 s.
wait_for() {
  local i
  for ((i = 0; i < 300; i++)); do
    [[ -e $1 ]] && return 0
    sleep 0.1
  done
  return 1
}

# same_pixels A B: prism diff's largest difference is 0, and idiff finds none.
same_pixels() {
  local max
  max=$("$PRISM" diff "$1" "$2" --metric max)
  [[ $max == 0 ]] && idiff -fail 0 -failpercent 0 -warn 0 "$1" "$2" >/dev/null
}

# interrupt SIGNAL: starts the checkpointed render, waits for its first checkpoint, sends
# SIGNAL and leaves the exit code in $code.
interrupt() {
  rm -f "$OUT" "$CKPT"
  # Job control, so that the background render does not start with SIGINT ignored.
  set -m
  "$PRISM" "${RUN[@]}" >"$TMP/stdout" 2>"$TMP/stderr" &
  local pid=$!
  set +m
  wait_for "$CKPT" || fail "$1: no checkpoint after 30 s"
  kill "-$1" "$pid"
  wait "$pid" 2>/dev/null
  code=$?
}

# resume WHAT: re-runs the command, which must resume, finish and match the whole render.
resume() {
  "$PRISM" "${RUN[@]}" >"$TMP/stdout" 2>"$TMP/stderr" || fail "$1: the re-run failed: $(cat "$TMP/stderr")"
  grep -qE "^prism: resuming .*out.exr from its checkpoint: [0-9]+ of $SPP samples per pixel done$" \
    "$TMP/stderr" || fail "$1: the re-run did not say it resumed: $(cat "$TMP/stderr")"
  grep -qE "^resumed +from .*out.exr.checkpoint at [0-9]+ of $SPP spp" "$TMP/stdout" ||
    fail "$1: the summary does not say it resumed: $(cat "$TMP/stdout")"
  grep -q "^rays .*camera 7,372,800," "$TMP/stdout" ||
    fail "$1: the rays of the whole image are not counted: $(grep ^rays "$TMP/stdout")"
  [[ -e $CKPT ]] && fail "$1: the checkpoint is left after the image was written"
  iinfo -v "$OUT" | grep -q 'prism:resumedSamples: "' || fail "$1: the EXR does not record the resume"
  same_pixels "$OUT" "$TMP/whole.exr" && echo "ok: $1: resumed, same pixels" ||
    fail "$1: the resumed image differs from the uninterrupted one"
}

# The uninterrupted render, on two threads and without checkpoints.
"$PRISM" render "$SCENE" -o "$TMP/whole.exr" --res 160x90 --spp "$SPP" --threads 2 --quiet ||
  fail "uninterrupted render"

interrupt TERM
[[ $code -eq 143 ]] || fail "SIGTERM: exit code $code, expected 143: $(cat "$TMP/stderr")"
[[ -e $OUT ]] && fail "SIGTERM: wrote $OUT"
[[ -e $CKPT ]] || fail "SIGTERM: no checkpoint"
grep -qE "^prism: stopped by SIGTERM after [0-9]+ of $SPP samples per pixel; saved .*out.exr.checkpoint" \
  "$TMP/stderr" || fail "SIGTERM: no stop message: $(cat "$TMP/stderr")"
grep -qF -- "prism: to resume, run: $PRISM render $SCENE -o $OUT --res 160x90" "$TMP/stderr" ||
  fail "SIGTERM: no resume command: $(cat "$TMP/stderr")"
resume "SIGTERM"

interrupt KILL
[[ $code -eq 137 ]] || fail "SIGKILL: exit code $code"
[[ -e $OUT ]] && fail "SIGKILL: wrote $OUT"
resume "SIGKILL"
ls -A "$TMP" | grep -q "\.tmp-" && fail "a temporary file was left: $(ls -A "$TMP")"

interrupt USR1
[[ $code -eq 138 ]] || fail "SIGUSR1: exit code $code, expected 138: $(cat "$TMP/stderr")"
[[ -e $OUT ]] && fail "SIGUSR1: wrote $OUT"
[[ -e $CKPT ]] || fail "SIGUSR1: no checkpoint"
# Another option: the checkpoint is not this render's, which starts over with a warning.
"$PRISM" render "$SCENE" -o "$OUT" --res 160x90 --spp 8 --checkpoint-interval 1 >"$TMP/stdout" \
  2>"$TMP/stderr" || fail "changed option: $(cat "$TMP/stderr")"
grep -qE "^prism: warning: .*out.exr.checkpoint: written for another job .*; rendering from the start$" \
  "$TMP/stderr" || fail "changed option: no warning: $(cat "$TMP/stderr")"
grep -q "^resumed" "$TMP/stdout" && fail "changed option: resumed anyway"
"$PRISM" render "$SCENE" -o "$TMP/fresh.exr" --res 160x90 --spp 8 --quiet || fail "fresh render"
same_pixels "$OUT" "$TMP/fresh.exr" && echo "ok: changed option: rendered from the start" ||
  fail "changed option: not the image of a fresh render"

interrupt INT
[[ $code -eq 130 ]] || fail "SIGINT: exit code $code, expected 130: $(cat "$TMP/stderr")"
[[ -e $OUT ]] && fail "SIGINT: wrote $OUT"
grep -q "^prism: interrupted by SIGINT: nothing written$" "$TMP/stderr" ||
  fail "SIGINT: no message: $(cat "$TMP/stderr")"

# Without --checkpoint-interval nothing is saved, and SIGTERM simply terminates.
rm -f "$OUT" "$CKPT"
"$PRISM" render "$SCENE" -o "$OUT" --res 32x18 --spp 4 --quiet || fail "render without checkpoints"
[[ -e $CKPT ]] && fail "a checkpoint without --checkpoint-interval"
expect 2 "--checkpoint-interval" -- render "$SCENE" -o "$TMP/bad.exr" --checkpoint-interval -1

echo "$failures failed"
[[ $failures -eq 0 ]]
