#!/usr/bin/env bash
# Short libFuzzer runs (ASan + UBSan) over the glTF loader, seeded with the shipped scenes and
# Debian's samples, and over the image path, seeded with an image of every format OpenImageIO
# knows: builds fuzz/gltf_loader_fuzz and fuzz/gltf_image_fuzz with clang (incrementally, next
# to the prism binary) and fails on any crash, leak or sanitizer report. The long runs are in
# docs/fuzzing.md.
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
bash "$SRC/fuzz/seed_corpus.sh" --images "$TMP/image-seeds" >/dev/null 2>&1
# run TARGET RUNS SEEDS: a fixed seed and run count, so that a failure here reproduces.
run() {
  local target=$1 runs=$2 seeds=$3
  mkdir -p "$TMP/$target-corpus" "$TMP/$target-artifacts"
  if ! TMPDIR="$TMP" "$OUT/$target" -seed=1 -runs="$runs" -max_len=262144 -rss_limit_mb=4096 \
      -artifact_prefix="$TMP/$target-artifacts/" "$TMP/$target-corpus" "$seeds" >"$TMP/fuzz.log" 2>&1; then
    tail -n 60 "$TMP/fuzz.log"
    for f in "$TMP/$target-artifacts"/*; do [[ -e $f ]] && echo "crashing input (base64): $(base64 -w0 "$f" | head -c 2000)"; done
    fail "libFuzzer found a problem in $target (see above)"
  fi
  echo "$target: $(grep -E "^Done|DONE" "$TMP/fuzz.log" | tail -n 1)"
}
run gltf_loader_fuzz 2000 "$TMP/seeds"
run gltf_image_fuzz 1000 "$TMP/image-seeds"
echo "$failures failed"
[[ $failures -eq 0 ]]
