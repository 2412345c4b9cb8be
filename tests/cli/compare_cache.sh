#!/usr/bin/env bash
# `prism compare`'s reference cache is bounded (--cache-limit, least recently used first) and
# can be emptied (--clear-cache, no scene needed). Usage: compare_cache.sh PRISM SOURCE_DIR
source "$(dirname "$0")/lib/common.bash" "$@"
SCENE="$SRC/scenes/spheres.gltf"
export XDG_CACHE_HOME="$TMP/cache"
CACHE="$TMP/cache/prism/references"
compare() { "$PRISM" compare "$SCENE" --res 32x24 --spp 1 --threads 2 --reference-integrator self -o "$TMP/report" "$@"; }
entries() { find "$CACHE" -name '*.exr' | wc -l; }

compare --integrators phong,whitted --reference-spp 4 >"$TMP/out1" || fail "first compare exited $?"
[[ $(entries) -eq 2 ]] || fail "expected 2 cached references, found $(entries)"
echo "not a reference" >"$CACHE/notes.txt"
# The whitted reference is used again: it becomes the most recently used of the two.
sleep 1.1
compare --integrators whitted --reference-spp 4 >"$TMP/out2" || fail "second compare exited $?"
grep -q "^reference whitted: .*from the cache" "$TMP/out2" || fail "whitted not found in the cache"
phong=$(grep -o "phong: .*cached as [^ ]*" "$TMP/out1" | sed 's/.*cached as //')
[[ -f "$phong" ]] || fail "no phong reference at '$phong'"

# A bound that holds about one reference: a new one (shadow) evicts the least recently used
# (phong), keeps itself and the newer whitted only if they fit.
size=$(stat -c %s "$phong")
limit=$(/usr/bin/python3 -c "print(($size * 2.5) / 2**30)")
sleep 1.1
compare --integrators shadow --reference-spp 4 --cache-limit "$limit" >"$TMP/out3" ||
  fail "third compare exited $?"
cat "$TMP/out3" | grep "^reference"
[[ ! -f "$phong" ]] || fail "the least recently used reference (phong) was kept"
grep -q "removed the 1 least recently used" "$TMP/out3" || fail "no eviction note"
[[ $(entries) -eq 2 ]] || fail "expected whitted and shadow left, found $(entries)"
[[ -f "$CACHE/notes.txt" ]] || fail "a file that is not a reference was removed"
echo "ok: --cache-limit evicted the least recently used reference only"

# A bound of 0 keeps only the reference just rendered.
compare --integrators phong --reference-spp 4 --cache-limit 0 >"$TMP/out4" || fail "fourth exited $?"
[[ $(entries) -eq 1 ]] || fail "--cache-limit 0: expected 1 entry, found $(entries)"

out=$("$PRISM" compare --clear-cache) || fail "--clear-cache exited $?"
[[ "$out" =~ ^removed\ 1\ cached\ references\ \([0-9,]+\ bytes\)\ from\ $CACHE$ ]] ||
  fail "--clear-cache printed: $out"
[[ $(entries) -eq 0 ]] || fail "--clear-cache left $(entries)"
[[ -f "$CACHE/notes.txt" ]] || fail "--clear-cache removed a file that is not a reference"
echo "ok: --clear-cache emptied the cache and needed no scene"

"$PRISM" compare "$SCENE" -o "$TMP/r" --cache-limit -1 2>"$TMP/err" && fail "--cache-limit -1 accepted"
[[ $(wc -l <"$TMP/err") -eq 1 ]] || fail "--cache-limit -1: not one line: $(cat "$TMP/err")"
echo "$failures failed"
[[ $failures -eq 0 ]]
