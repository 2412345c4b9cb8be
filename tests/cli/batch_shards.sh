#!/usr/bin/env bash
# `prism batch --shard K/N` (session/batch.h, docs/batch-scheduling.md): for N = 1, 2, 3, 5 the
# shards of a 12-render file are disjoint and together exactly the whole list, the split
# follows the estimated cost rather than the count, the same file gives the same split every
# time, two shards rendered one after the other write every output exactly once with a
# report each, and a malformed --shard is a one-line usage error (exit 2).
# Usage: batch_shards.sh PRISM SOURCE_DIR
source "$(dirname "$0")/lib/common.bash" "$@"
set -eo pipefail

# Not $TMP/out: lib/common.bash's expect writes that file.
OUT="$TMP/renders"
mkdir -p "$OUT"
# 12 renders: lists of integrators and spp values over the three shipped scenes, small
# enough that rendering them all takes a few seconds on one thread.
cat >"$TMP/jobs.json" <<EOF
{
  "version": 1,
  "defaults": {"res": "64x48"},
  "jobs": [
    {"name": "w", "scene": "$SRC/scenes/whitted.gltf", "integrator": ["phong", "shadow", "whitted"],
     "spp": [1, 2], "output": "$OUT/{job}-{scene}-{integrator}-{spp}.exr"},
    {"name": "s", "scene": "$SRC/scenes/spheres.gltf", "integrator": ["phong", "whitted"],
     "spp": [1, 4], "output": "$OUT/{job}-{scene}-{integrator}-{spp}.exr"},
    {"name": "f", "scene": "$SRC/scenes/furnace.gltf", "integrator": "shadow",
     "spp": [2, 4], "output": "$OUT/{job}-{scene}-{integrator}-{spp}.exr"}
  ]
}
EOF

# outputs FILE ARGS...: the output paths `prism batch FILE --dry-run ARGS` lists, one a line
# (a dry-run line ends "-> PATH  [state]"); fails the test when the command does.
outputs() {
  local file=$1
  shift
  "$PRISM" batch "$file" --dry-run "$@" >"$TMP/dry" 2>"$TMP/dry.err" ||
    { fail "batch $file --dry-run $* exited $?: $(cat "$TMP/dry.err")"; return 0; }
  sed -n 's/.*  -> \(.*\)  \[.*\]$/\1/p' "$TMP/dry"
}

outputs "$TMP/jobs.json" | sort >"$TMP/all"
[[ $(wc -l <"$TMP/all") -eq 12 ]] || fail "the file expands into $(wc -l <"$TMP/all") renders, expected 12"
[[ $(sort -u "$TMP/all" | wc -l) -eq 12 ]] || fail "two renders share an output path"
outputs "$TMP/jobs.json" --shard 0/1 | sort >"$TMP/one"
cmp -s "$TMP/all" "$TMP/one" || fail "--shard 0/1 is not the whole list"

for n in 1 2 3 5; do
  : >"$TMP/union"
  counts=()
  for ((k = 0; k < n; k++)); do
    outputs "$TMP/jobs.json" --shard "$k/$n" >"$TMP/shard-$k"
    # Deterministic: a second plan of the same file gives the same shard, line for line.
    outputs "$TMP/jobs.json" --shard "$k/$n" >"$TMP/again"
    cmp -s "$TMP/shard-$k" "$TMP/again" || fail "--shard $k/$n differs from one run to the next"
    grep -q "renders in shard $k/$n\$\|^[0-9]* renders\$" "$TMP/dry" ||
      fail "--shard $k/$n: no closing count line: $(tail -1 "$TMP/dry")"
    counts+=("$(wc -l <"$TMP/shard-$k")")
    cat "$TMP/shard-$k" >>"$TMP/union"
  done
  # Disjoint (no path twice) and complete (the union is the N=1 list).
  dups=$(sort "$TMP/union" | uniq -d)
  [[ -z $dups ]] || fail "N=$n: outputs in more than one shard: $dups"
  sort -u "$TMP/union" | cmp -s - "$TMP/all" || fail "N=$n: the shards together are not the whole list"
  echo "ok: N=$n: shards of ${counts[*]} renders, disjoint, union the whole list, same twice"
done

# By cost, not count: one render of 16 spp (16x the pixels x spp of each of the 8 others, same
# integrator, same size) outweighs them all, so with 2 shards it sits alone and the other
# shard takes the 8; a split by count would give 4 and 5.
{
  echo '{"version": 1, "defaults": {"res": "64x48", "integrator": "phong"}, "jobs": ['
  for i in 1 2 3 4 5 6 7 8; do
    echo "{\"name\": \"light$i\", \"scene\": \"$SRC/scenes/spheres.gltf\", \"spp\": 1,"
    echo " \"output\": \"$OUT/heavy-light$i.exr\"},"
  done
  echo "{\"name\": \"big\", \"scene\": \"$SRC/scenes/spheres.gltf\", \"spp\": 16,"
  echo " \"output\": \"$OUT/heavy-big.exr\"}]}"
} >"$TMP/heavy.json"
outputs "$TMP/heavy.json" --shard 0/2 >"$TMP/heavy-0"
outputs "$TMP/heavy.json" --shard 1/2 >"$TMP/heavy-1"
for k in 0 1; do
  if grep -q 'heavy-big.exr$' "$TMP/heavy-$k"; then
    [[ $(wc -l <"$TMP/heavy-$k") -eq 1 ]] ||
      fail "the costly render shares shard $k/2 with others: $(tr '\n' ' ' <"$TMP/heavy-$k")"
    [[ $(wc -l <"$TMP/heavy-$((1 - k))") -eq 8 ]] ||
      fail "shard $((1 - k))/2 has $(wc -l <"$TMP/heavy-$((1 - k))") renders, expected the 8 light ones"
    echo "ok: the 16x render is alone in shard $k/2, the other has $(wc -l <"$TMP/heavy-$((1 - k))")"
  fi
done
cat "$TMP/heavy-0" "$TMP/heavy-1" | grep -c 'heavy-big.exr$' | grep -qx 1 ||
  fail "the costly render is not in exactly one shard"

# Render the 12 in two shards, one after the other, one thread each.
for k in 0 1; do
  "$PRISM" batch "$TMP/jobs.json" --shard "$k/2" --threads 1 >"$TMP/run-$k.out" 2>"$TMP/run-$k.err" ||
    fail "--shard $k/2 exited $?: $(cat "$TMP/run-$k.err")"
  grep -q "^report .*batch-report-$k-of-2.json$" "$TMP/run-$k.out" ||
    fail "--shard $k/2 does not name its report: $(tail -2 "$TMP/run-$k.out")"
done
while read -r path; do
  [[ -s $path ]] || fail "missing output $path"
done <"$TMP/all"
# Every output once: 12 EXRs (and nothing else that looks like one), no temporary left.
[[ $(find "$OUT" -name '*.exr' ! -name 'heavy-*' | wc -l) -eq 12 ]] ||
  fail "$(find "$OUT" -name '*.exr' | wc -l) EXRs written, expected 12: $(ls "$OUT")"
# The reports: each lists its own shard's outputs, all rendered; together every output once.
/usr/bin/python3 - "$OUT" "$TMP/all" <<'EOF' || fail "the shard reports are not what was rendered"
import json, sys
folder, expected = sys.argv[1], sorted(open(sys.argv[2]).read().split())
seen = []
for k in (0, 1):
    report = json.load(open(f"{folder}/batch-report-{k}-of-2.json"))
    assert report["shard"] == f"{k}/2", report["shard"]
    for job in report["jobs"]:
        assert job["status"] == "rendered", (k, job["output"], job["status"], job["error"])
        seen.append(job["output"])
    print(f"shard {k}/2: {len(report['jobs'])} rendered in {report['wall_seconds']:.2f} s")
assert sorted(seen) == expected, (sorted(seen), expected)
EOF

# A rerun of a shard finds its jobs up to date.
"$PRISM" batch "$TMP/jobs.json" --shard 1/2 --threads 1 --quiet ||
  fail "rerun of --shard 1/2 exited $?"
/usr/bin/python3 -c 'import json,sys; r=json.load(open(sys.argv[1])); assert all(j["status"]=="skipped" for j in r["jobs"]), r["counts"]' \
  "$OUT/batch-report-1-of-2.json" || fail "rerun of --shard 1/2 did not skip its up-to-date jobs"

# A shard that is not K/N with 0 <= K < N: one line, exit 2, before anything else.
set +e
for bad in 2/2 -1/3 x 1/0 3 1/2/3; do
  expect 2 "^prism: error: --shard $bad: expected K/N with 0 <= K < N" -- batch "$TMP/jobs.json" --shard "$bad"
done

echo "$failures failed"
[[ $failures -eq 0 ]]
