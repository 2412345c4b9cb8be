#!/usr/bin/env bash
# `prism batch` end to end: a job file's schema errors (exit 2, one line each, nothing
# rendered; --keep-going renders the rest), failing jobs that leave the others alone (exit 1,
# the report names them), skipping up-to-date outputs and re-rendering exactly what changed,
# outputs identical to `prism render`'s, "camera": "all", a SIGKILL that leaves no partial
# file, SIGTERM checkpoints that resume bit-identically, SIGINT, and --dry-run.
# Usage: batch.sh PRISM SOURCE_DIR
source "$(dirname "$0")/lib/common.bash" "$@"
CAMERAS=/usr/share/assimp/models/glTF2/cameras  # Cameras.gltf: 2 cameras, an external .bin
cd "$TMP" || exit 1
cp "$SRC/scenes/spheres.gltf" "$SRC/scenes/whitted.gltf" .
cp "$CAMERAS/Cameras.gltf" "$CAMERAS/simpleSquare.bin" .

# report DIR PYTHON: runs PYTHON with r = DIR/batch-report.json and s = "name=status ..."
# (the jobs in report order).
report() {
  python3 -c "
import json, sys
r = json.load(open('$1/batch-report.json'))
s = ' '.join(j['name'] + '=' + j['status'] for j in r['jobs'])
$2" 2>/dev/null || echo "(no readable report in $1)"
}
# outputs DIR: the files prism left in DIR, the report aside.
outputs() { ls -A "$1" | grep -v '^batch-report.json$' | tr '\n' ' '; }
# hashes FILE...: each file's name and the SHA-1 of its pixels, reading every pixel (a
# truncated file fails).
hashes() { iinfo --hash "$@" | awk '/SHA-1/ {print name, $2} !/SHA-1/ {name = $1}'; }
# wait_for FILE [COUNT]: true once FILE exists (with COUNT, once COUNT files match the glob
# FILE), false after 30 s.
wait_for() {
  local i n
  for ((i = 0; i < 300; i++)); do
    # shellcheck disable=SC2086
    n=$(compgen -G "$1" | wc -l)
    ((n >= ${2:-1})) && return 0
    sleep 0.1
  done
  return 1
}
# start_batch OUT ERR ARGS...: prism batch ARGS in the background, with job control so that
# SIGINT is not ignored; its pid in $pid.
start_batch() {
  local out=$1 err=$2
  shift 2
  set -m
  "$PRISM" batch "$@" >"$out" 2>"$err" &
  pid=$!
  set +m
}

# ---- Schema errors: exit 2, one error line naming the job, its name and the field, nothing
# rendered; with --keep-going the valid job renders and the invalid one is failed.
GOOD='{"name": "good", "scene": "spheres.gltf", "output": "s/good.exr"}'
# schema NAME JOBS PATTERN [VERSION]: a file with the list JOBS must fail with one line
# matching PATTERN.
schema() {
  local name=$1 jobs=$2 pattern=$3 version=${4:-1}
  rm -rf s && mkdir s
  printf '{"version": %s, "defaults": {"res": "16x9", "spp": 1}, "jobs": [%s]}\n' "$version" \
    "$jobs" >s.json
  "$PRISM" batch s.json --threads 1 --quiet >out 2>err
  local code=$?
  local errors
  errors=$(grep -c '^prism: error:' err)
  if [[ $code -ne 2 ]]; then
    fail "schema $name: exit $code, expected 2: $(cat err)"
  elif [[ $errors -ne 1 ]] || ! grep -qE -- "^prism: error: s.json: $pattern" err; then
    fail "schema $name: expected one error line matching '$pattern': $(cat err)"
  elif [[ -n $(ls -A s) ]]; then
    fail "schema $name: rendered $(outputs s)"
  else
    echo "ok: schema $name: $(grep '^prism: error:' err)"
  fi
}
X='"name": "x", "scene": "spheres.gltf"'
schema "unknown key" "$GOOD, {$X, \"output\": \"s/x.exr\", \"colour\": 3}" \
  "jobs\[1\] 'x': colour: no such key"
schema "spp many" "$GOOD, {$X, \"output\": \"s/x.exr\", \"spp\": \"many\"}" "jobs\[1\] 'x': spp: .*many"
schema "spp 0" "$GOOD, {$X, \"output\": \"s/x.exr\", \"spp\": 0}" "jobs\[1\] 'x': spp: must be a whole number from 1 to 65536, not 0"
schema "integrator" "$GOOD, {$X, \"output\": \"s/x.exr\", \"integrator\": \"raymarch\"}" \
  "jobs\[1\] 'x': integrator: raymarch: expected phong, shadow, whitted or path"
schema "no scene" "$GOOD, "'{"name": "x", "output": "s/x.exr"}' "jobs\[1\] 'x': scene: missing"
schema "no output" "$GOOD, {$X}" "jobs\[1\] 'x': output: missing"
schema "threads" "$GOOD, {$X, \"output\": \"s/x.exr\", \"threads\": 2}" \
  "jobs\[1\] 'x': threads: is set for the whole batch"
schema "placeholder" "$GOOD, {$X, \"output\": \"s/{foo}.exr\"}" "jobs\[1\] 'x': output: .*\{foo\}"
schema "collision" "$GOOD, "'{"name": "x", "scene": "whitted.gltf", "output": "s/good.exr"}' \
  "jobs\[1\] 'x' and jobs\[0\] 'good' would both write .*s/good.exr"
schema "version 2" "$GOOD" "version: 2: this Prism reads version 1" 2
schema "empty list" "" "jobs: must be a list of at least one job"
# A valid job's missing output folder is not made when another job is invalid.
schema "no folder made" '{"name": "new", "scene": "spheres.gltf", "output": "s/new/{scene}.exr"}, '"{$X, \"output\": \"s/x.exr\", \"spp\": 0}" \
  "jobs\[1\] 'x': spp: must be a whole number"
# Every camera of a file with two, into one name.
schema "camera all" "$GOOD, "'{"name": "x", "scene": "Cameras.gltf", "camera": "all", "output": "s/c.exr"}' \
  "jobs\[1\] 'x' \(camera cameras_1_\) and jobs\[1\] 'x' \(camera cameras_0_\) would both write .*s/c.exr"

# keep_going NAME JOB PATTERN: with --keep-going, GOOD renders and JOB is failed in the report
# with an error matching PATTERN; exit 1.
keep_going() {
  rm -rf s && mkdir s
  printf '{"version": 1, "defaults": {"res": "16x9", "spp": 1}, "jobs": [%s, %s]}\n' "$GOOD" \
    "$2" >s.json
  "$PRISM" batch s.json --threads 1 --quiet --keep-going >out 2>err
  local code=$?
  [[ $code -eq 1 ]] || fail "--keep-going $1: exit $code, expected 1: $(cat err)"
  [[ $(outputs s) == "good.exr " ]] || fail "--keep-going $1: wrote '$(outputs s)'"
  local got
  got=$(report s "print(s); print(r['jobs'][1]['error'])")
  [[ $(head -1 <<<"$got") == "good=rendered x=failed" ]] && grep -qE -- "$3" <<<"$got" &&
    echo "ok: --keep-going $1: $(tail -1 <<<"$got")" || fail "--keep-going $1: report says $got"
}
keep_going "unknown key" "{$X, \"output\": \"s/x.exr\", \"colour\": 3}" "^colour: no such key"
keep_going "spp 0" "{$X, \"output\": \"s/x.exr\", \"spp\": 0}" "^spp: "
keep_going "no scene" '{"name": "x", "output": "s/x.exr"}' "^scene: missing"
keep_going "placeholder" "{$X, \"output\": \"s/{foo}.exr\"}" "^output: .*\{foo\}"

# ---- Jobs that fail leave the others alone: a broken scene, an output under a regular file
# and a camera the scene lacks fail with their reasons, exit 1, and the rest render.
mkdir f
head -c 300 spheres.gltf >f/broken.gltf  # cut inside its JSON
touch f/plain
cat >f/jobs.json <<EOF
{"version": 1, "defaults": {"res": "16x9", "spp": 1}, "jobs": [
  {"name": "ok1", "scene": "../spheres.gltf", "output": "ok1.exr"},
  {"name": "broken", "scene": "broken.gltf", "output": "broken.exr"},
  {"name": "ok2", "scene": "../whitted.gltf", "output": "ok2.exr"},
  {"name": "unwritable", "scene": "../spheres.gltf", "output": "plain/x.exr"},
  {"name": "badcam", "scene": "../spheres.gltf", "camera": "nosuch", "output": "badcam.exr"},
  {"name": "ok3", "scene": "../spheres.gltf", "output": "ok3.exr", "integrator": "phong"}]}
EOF
before=$failures
"$PRISM" batch f/jobs.json --threads 1 --report f/batch-report.json >out 2>err
code=$?
[[ $code -eq 1 ]] || fail "failing jobs: exit $code, expected 1: $(cat err)"
[[ $(outputs f) == "broken.gltf jobs.json ok1.exr ok2.exr ok3.exr plain " ]] ||
  fail "failing jobs: the folder holds $(outputs f)"
got=$(report f "print(s); [print(j['name'], j['error']) for j in r['jobs'] if j['error']]")
expected="ok1=rendered broken=failed ok2=rendered unwritable=failed badcam=failed ok3=rendered"
[[ $(head -1 <<<"$got") == "$expected" ]] || fail "failing jobs: statuses $(head -1 <<<"$got")"
grep -qE "^broken .*broken.gltf.*JSON" <<<"$got" || fail "failing jobs: broken scene's error: $got"
grep -qE "^unwritable output: .*plain/x.exr" <<<"$got" || fail "failing jobs: output's error: $got"
grep -qE "^badcam camera: nosuch: .*no such camera" <<<"$got" ||
  fail "failing jobs: camera's error: $got"
[[ $(wc -l <<<"$got") -eq 4 ]] || fail "failing jobs: errors beside the three: $got"
# Off a terminal the progress is one line per job, naming it and what became of it.
grep -qE "^prism: \[[1-6]/6\] failed jobs\[1\] 'broken' [0-9.]+ s: .*broken.gltf" err &&
  grep -qE "^prism: \[[1-6]/6\] rendered jobs\[5\] 'ok3' [0-9.]+ s$" err ||
  fail "failing jobs: progress lines do not name the jobs: $(cat err)"
[[ $failures -eq $before ]] && echo "ok: failing jobs: $(tail -n +2 <<<"$got" | tr '\n' ';')"

# ---- Output folders that do not exist yet are made when their job starts, as deep as the
# placeholders spread them; one under a regular file fails that job alone.
mkdir d
touch d/plain
cat >d/jobs.json <<EOF
{"version": 1, "defaults": {"res": "16x9"}, "jobs": [
  {"name": "deep", "scene": "../spheres.gltf", "spp": [1, 2], "output": "out/{scene}/{spp}.exr",
   "preview": "png/{scene}-{spp}.png"},
  {"name": "under-file", "scene": "../spheres.gltf", "output": "plain/sub/x.exr"}]}
EOF
"$PRISM" batch d/jobs.json --threads 1 --quiet >out 2>err
code=$?
got=$(report d "print(s); [print(j['name'], j['error']) for j in r['jobs'] if j['error']]")
if [[ $code -ne 1 ]]; then
  fail "output folders: exit $code, expected 1: $(cat err)"
elif [[ $(head -1 <<<"$got") != "deep=rendered deep=rendered under-file=failed" ]]; then
  fail "output folders: statuses $got"
elif ! grep -qE "^under-file output: .*plain/sub/x.exr: .*plain is not a directory" <<<"$got"; then
  fail "output folders: the error under a file: $got"
elif [[ $(hashes d/out/spheres/1.exr d/out/spheres/2.exr | wc -l) -ne 2 ]] ||
  [[ ! -s d/png/spheres-1.png || ! -s d/png/spheres-2.png ]]; then
  fail "output folders: made $(find d -type f | sort | tr '\n' ' ')"
else
  echo "ok: output folders: $(cd d && find out png -type f | sort | tr '\n' ' ')"
fi

# ---- Up to date: a re-run skips everything; a changed setting, a changed scene file (the
# .gltf or its .bin), --force and a deleted output re-render exactly what they touch.
mkdir r
cat >r/jobs.json <<EOF
{"version": 1, "defaults": {"res": "48x27", "spp": 2}, "jobs": [
  {"name": "s1", "scene": "../spheres.gltf", "output": "s1.exr"},
  {"name": "s2", "scene": "../spheres.gltf", "output": "s2.exr", "integrator": "phong"},
  {"name": "w1", "scene": "../whitted.gltf", "output": "w1.exr"},
  {"name": "w2", "scene": "../whitted.gltf", "output": "w2.exr", "spp": 3},
  {"name": "c", "scene": "../Cameras.gltf", "camera": "all", "output": "c-{camera}.exr"}]}
EOF
# rerun WHAT EXPECTED [ARGS...]: runs the batch, whose statuses must be EXPECTED.
rerun() {
  local what=$1 expected=$2
  shift 2
  "$PRISM" batch r/jobs.json --threads 2 --quiet "$@" >out 2>err || fail "$what: exit $?: $(cat err)"
  local got
  got=$(report r "print(s)")
  [[ $got == "$expected" ]] && echo "ok: $what: $got" || fail "$what: $got, expected $expected"
}
all="s1=rendered s2=rendered w1=rendered w2=rendered c=rendered c=rendered"
rerun "first run" "$all"
[[ $(outputs r) == "c-cameras_0_.exr c-cameras_1_.exr jobs.json s1.exr s2.exr w1.exr w2.exr " ]] ||
  fail "camera all: the folder holds $(outputs r)"
rerun "re-run" "s1=skipped s2=skipped w1=skipped w2=skipped c=skipped c=skipped"
sed -i 's/"spp": 3/"spp": 4/' r/jobs.json
rerun "w2's spp changed" "s1=skipped s2=skipped w1=skipped w2=rendered c=skipped c=skipped"
echo " " >>whitted.gltf
rerun "whitted.gltf changed" "s1=skipped s2=skipped w1=rendered w2=rendered c=skipped c=skipped"
# The first triangle's last two indices swapped: the same size, other content.
printf '\x02\x00\x01\x00' | dd of=simpleSquare.bin bs=1 seek=2 conv=notrunc status=none
rerun "simpleSquare.bin changed" "s1=skipped s2=skipped w1=skipped w2=skipped c=rendered c=rendered"
rerun "--force" "$all" --force
rm r/s2.exr
rerun "s2.exr deleted" "s1=skipped s2=rendered w1=skipped w2=skipped c=skipped c=skipped"

# ---- The same pixels as `prism render` with the same settings, a camera by index too.
"$PRISM" render spheres.gltf -o r-s1.exr --res 48x27 --spp 2 --quiet || fail "prism render s1"
"$PRISM" render Cameras.gltf -o r-c1.exr --res 48x27 --spp 2 --camera 1 --quiet 2>/dev/null ||
  fail "prism render camera 1"
for pair in "r-s1.exr r/s1.exr" "r-c1.exr r/c-cameras_1_.exr"; do
  # shellcheck disable=SC2086
  max=$("$PRISM" diff $pair --metric max)
  [[ $max == 0 ]] && echo "ok: $pair: the same pixels" || fail "$pair: max difference $max"
done

# ---- --dry-run: one line per render, nothing written.
mkdir k ref dry
cat >k/jobs.json <<EOF
{"version": 1, "defaults": {"res": "160x90", "scene": "$TMP/whitted.gltf"}, "jobs": [
  {"name": "k", "output": "{integrator}-{spp}.exr", "integrator": ["shadow", "whitted"],
   "spp": [12, 14, 16, 18]}]}
EOF
cp k/jobs.json ref/
cp k/jobs.json dry/
"$PRISM" batch dry/jobs.json --dry-run >out 2>err || fail "--dry-run: exit $?: $(cat err)"
renders=$(grep -cE "^ +[0-7]  jobs\[0\] 'k' \(integrator (shadow|whitted), spp 1[2468]\) .* -> dry/(shadow|whitted)-1[2468].exr  \[to render\]$" out)
[[ $renders -eq 8 && $(tail -1 out) == "8 renders" && $(wc -l <out) -eq 9 ]] ||
  fail "--dry-run printed: $(cat out)"
[[ $(outputs dry) == "jobs.json " ]] && echo "ok: --dry-run: 8 renders, nothing written" ||
  fail "--dry-run wrote $(outputs dry)"

# ---- SIGKILL mid-batch: every output is absent or complete; a re-run completes them all,
# identical to an uninterrupted run.
"$PRISM" batch ref/jobs.json --threads 2 --quiet || fail "uninterrupted batch"
names=$(cd ref && ls -- *.exr)
start_batch out err k/jobs.json --threads 1 --quiet
wait_for "k/*.exr" 3 || fail "SIGKILL: no third output after 30 s"
kill -KILL "$pid"
wait "$pid" 2>/dev/null
code=$?
[[ $code -eq 137 ]] || fail "SIGKILL: exit $code"
done_before=$(cd k && ls -- *.exr)
echo "ok: SIGKILL after: $(tr '\n' ' ' <<<"$done_before")(the folder: $(outputs k))"
# Whatever an output's name holds reads in full and is the uninterrupted run's.
# shellcheck disable=SC2086
(cd k && hashes $done_before) >k.hashes 2>&1 || fail "SIGKILL: an output does not read: $(cat k.hashes)"
# shellcheck disable=SC2086
(cd ref && hashes $done_before) >ref.hashes
diff ref.hashes k.hashes >/dev/null || fail "SIGKILL: outputs differ from the reference: $(cat k.hashes)"
"$PRISM" batch k/jobs.json --threads 2 --quiet >out 2>err || fail "after SIGKILL: exit $?: $(cat err)"
skipped=$(report k "print(sum(j['status'] == 'skipped' for j in r['jobs']))")
[[ $skipped -eq $(wc -w <<<"$done_before") ]] || fail "after SIGKILL: $skipped skipped"
# shellcheck disable=SC2086
(cd k && hashes $names) >k.hashes
# shellcheck disable=SC2086
(cd ref && hashes $names) >ref.hashes
[[ $(wc -l <ref.hashes) -eq 8 ]] && diff ref.hashes k.hashes >/dev/null &&
  echo "ok: after SIGKILL: the 8 outputs are the uninterrupted run's" ||
  fail "after SIGKILL: outputs differ: $(diff ref.hashes k.hashes)"
[[ $(outputs k) == "$(outputs ref)" ]] || fail "after SIGKILL: left over: $(outputs k)"

# ---- SIGINT: the running job is abandoned, nothing half-written, and the message says how
# to resume.
mkdir i
cp k/jobs.json i/
# --shard 0/1 is every job, but the resume command must carry it as every option that
# chooses the jobs.
start_batch out err i/jobs.json --threads 1 --quiet --shard 0/1
wait_for "i/*.exr" 1 || fail "SIGINT: no first output after 30 s"
kill -INT "$pid"
wait "$pid"
code=$?
[[ $code -eq 130 ]] || fail "SIGINT: exit $code, expected 130: $(cat err)"
grep -qE "^prism: stopped by SIGINT: .*to resume, run: prism batch i/jobs.json --shard 0/1$" err ||
  fail "SIGINT: no resume message: $(cat err)"
written=$(cd i && ls -- *.exr)
# shellcheck disable=SC2086
(cd i && hashes $written) >i.hashes
# shellcheck disable=SC2086
(cd ref && hashes $written) >ref.hashes
diff ref.hashes i.hashes >/dev/null && [[ $(wc -l <i.hashes) -lt 8 ]] &&
  echo "ok: SIGINT: exit 130, complete outputs: $(tr '\n' ' ' <<<"$written")" ||
  fail "SIGINT: outputs: $(cat i.hashes)"
others=$(ls -A i | grep -v -e '\.exr$' -e '^jobs.json$' -e '^batch-report.json$')
[[ -z $others ]] || fail "SIGINT: left over: $others"

# ---- A long job: SIGTERM saves its checkpoint (exit 143, no image); the re-run resumes
# and writes the uninterrupted image; the same after a SIGKILL once a checkpoint exists.
# Several seconds on one thread, so that checkpoints every second exist before it ends.
mkdir c
cat >c/jobs.json <<EOF
{"version": 1, "jobs": [
  {"name": "long", "scene": "../spheres.gltf", "output": "long.exr", "res": "160x90", "spp": 1024}]}
EOF
"$PRISM" render spheres.gltf -o whole.exr --res 160x90 --spp 1024 --threads 2 --quiet ||
  fail "uninterrupted long render"
LONG=(c/jobs.json --threads 1 --checkpoint-interval 1 --quiet)
# resume WHAT: the re-run resumes, finishes and matches the uninterrupted render.
resume() {
  "$PRISM" batch "${LONG[@]}" >out 2>err || fail "$1: the re-run failed: $(cat err)"
  local got
  got=$(report c "j = r['jobs'][0]; print(j['status'], j['resumed_samples'] > 0, j['resumed_samples'])")
  [[ $got == "rendered True "* ]] || fail "$1: the re-run's report says $got"
  [[ -e c/long.exr.checkpoint ]] && fail "$1: the checkpoint is left after the image was written"
  max=$("$PRISM" diff c/long.exr whole.exr --metric max)
  [[ $max == 0 ]] && echo "ok: $1: resumed from ${got##* } spp, same pixels" ||
    fail "$1: the resumed image differs by $max"
}
start_batch out err "${LONG[@]}"
wait_for c/long.exr.checkpoint || fail "SIGTERM: no checkpoint after 30 s"
kill -TERM "$pid"
wait "$pid"
code=$?
[[ $code -eq 143 ]] || fail "SIGTERM: exit $code, expected 143: $(cat err)"
[[ -e c/long.exr ]] && fail "SIGTERM: wrote c/long.exr"
[[ -e c/long.exr.checkpoint ]] || fail "SIGTERM: no checkpoint"
grep -qE "^prism: stopped by SIGTERM: .*saved a checkpoint; to resume, run: prism batch c/jobs.json" err ||
  fail "SIGTERM: no resume command: $(cat err)"
resume "SIGTERM"
rm c/long.exr
start_batch out err "${LONG[@]}"
wait_for c/long.exr.checkpoint || fail "SIGKILL: no checkpoint after 30 s"
kill -KILL "$pid"
wait "$pid" 2>/dev/null
[[ -e c/long.exr ]] && fail "SIGKILL: wrote c/long.exr"
resume "SIGKILL"

echo "$failures failed"
[[ $failures -eq 0 ]]
