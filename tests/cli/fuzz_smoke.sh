#!/usr/bin/env bash
# A short libFuzzer run over the glTF loader (ASan + UBSan), seeded with the shipped scenes and
# Debian's samples: builds fuzz/gltf_loader_fuzz with clang (incrementally, next to the prism
# binary) and fails on any crash, leak or sanitizer report. The long run is in docs/fuzzing.md.
# Usage: fuzz_smoke.sh PRISM SOURCE_DIR
source "$(dirname "$0")/lib/common.bash" "$@"

if ! command -v clang++ >/dev/null || ! ls /usr/lib/llvm-*/lib/clang/*/lib/linux/libclang_rt.fuzzer-x86_64.a >/dev/null 2>&1; then
  echo "FAIL: clang or libFuzzer (libclang-rt-14-dev) is missing; run scripts/setup.sh"
  exit 1
fi
OUT="$(dirname "$PRISM")/../fuzz-smoke"
if ! bash "$SRC/fuzz/build.sh" "$OUT" >"$TMP/build.log" 2>&1; then
  cat "$TMP/build.log"
  echo "FAIL: fuzz/build.sh failed"
  exit 1
fi
bash "$SRC/fuzz/seed_corpus.sh" "$TMP/seeds" >/dev/null
mkdir -p "$TMP/corpus" "$TMP/artifacts"
# Fixed seed and run count: the same inputs every time, so a failure here reproduces.
if ! TMPDIR="$TMP" "$OUT/gltf_loader_fuzz" -seed=1 -runs=2000 -max_len=262144 -rss_limit_mb=4096 \
    -artifact_prefix="$TMP/artifacts/" "$TMP/corpus" "$TMP/seeds" >"$TMP/fuzz.log" 2>&1; then
  tail -n 60 "$TMP/fuzz.log"
  for f in "$TMP"/artifacts/*; do [[ -e $f ]] && echo "crashing input (base64): $(base64 -w0 "$f" | head -c 2000)"; done
  fail "libFuzzer found a problem (see above)"
fi
grep -E "^Done|DONE" "$TMP/fuzz.log" | tail -n 1
echo "$failures failed"
[[ $failures -eq 0 ]]
