#!/usr/bin/env bash
# Builds the libFuzzer targets fuzz/gltf_loader_fuzz (the whole loader) and fuzz/gltf_image_fuzz
# (the image path alone) with Debian's clang, ASan and UBSan:
#   bash fuzz/build.sh [OUT_DIR]        (default build-fuzzer/)
# A plain clang command line rather than a CMake configuration: the fuzzer needs only
# scene_io and header-only parts of the renderer, and the main build uses g++. tinygltf and
# stb_image are compiled in from their headers so that they are instrumented as well.
# Rebuilds only what changed, so tests/cli/fuzz_smoke.sh can call it every time.
set -euo pipefail
SRC=$(cd "$(dirname "$0")/.." && pwd)
OUT=$(mkdir -p "${1:-$SRC/build-fuzzer}" && cd "${1:-$SRC/build-fuzzer}" && pwd)
CXX=${CXX_FUZZ:-clang++}
if ! command -v "$CXX" >/dev/null; then
  echo "fuzz/build.sh: $CXX not found; run scripts/setup.sh (installs clang and libclang-rt-14-dev)" >&2
  exit 1
fi
# -fsanitize=fuzzer-no-link everywhere but the final link, which adds libFuzzer's main().
SAN="-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer"
FLAGS=(-std=c++20 -O1 -g $SAN -fsanitize=fuzzer-no-link -I"$SRC" -I/usr/include/Imath
       -I/usr/include/stb -DNDEBUG)

# compile SOURCE OBJECT EXTRA_FLAGS...: when the object is older than the source or any
# project header (system headers only change with a package upgrade: delete OUT then).
compile() {
  local src=$1 obj=$2
  shift 2
  if [[ -f $obj ]] && [[ $obj -nt $src ]] &&
     [[ -z $(find "$SRC/scene_io" "$SRC/renderer" -name '*.h' -newer "$obj" -print -quit) ]]; then
    return 0
  fi
  echo "fuzz/build.sh: compiling $(basename "$src")"
  "$CXX" "${FLAGS[@]}" "$@" -c "$src" -o "$obj"
}

# At most FUZZ_JOBS compilers at once (default 2: the machine's cores are shared).
JOBS=${FUZZ_JOBS:-2}
failed=0
throttle() {
  while (($(jobs -rp | wc -l) >= JOBS)); do wait -n || failed=1; done
}
rm -f "$OUT/gltf_loader_fuzz.o"  # a main() from the layout before main/ would link twice
throttle; compile "$SRC/fuzz/tinygltf_impl.cpp" "$OUT/tinygltf_impl.o" -w &
# The Draco module is linked in rather than loaded (draco_module_linked.cpp); its build
# symbol needs a version header, which CMake would generate.
rm -f "$OUT/draco_module_loader.o"
mkdir -p "$OUT/generated/renderer"
[[ -f $OUT/generated/renderer/version.h ]] ||
  sed 's/@PROJECT_VERSION@/fuzz/; s/@PRISM_GIT_COMMIT@/fuzz/' "$SRC/renderer/version.h.in" \
    >"$OUT/generated/renderer/version.h"
for src in "$SRC"/scene_io/*.cpp "$SRC"/scene_io/draco/*.cpp "$SRC/fuzz/draco_module_linked.cpp"; do
  f=$(basename "$src" .cpp)
  [[ $f == draco_module_loader ]] && continue
  throttle; compile "$src" "$OUT/$f.o" -Wall -Wextra -Werror -I"$OUT/generated" &
done
mkdir -p "$OUT/main"
for target in gltf_loader_fuzz gltf_image_fuzz; do
  throttle; compile "$SRC/fuzz/$target.cpp" "$OUT/main/$target.o" -Wall -Wextra -Werror &
done
# The loader generates tangents for normal-mapped primitives without TANGENT.
throttle; compile "$SRC/renderer/geometry/tangents.cpp" "$OUT/tangents.o" -Wall -Wextra -Werror &
while (($(jobs -rp | wc -l) > 0)); do wait -n || failed=1; done
if ((failed)); then
  echo "fuzz/build.sh: a compilation failed" >&2
  exit 1
fi

# libdraco (KHR_draco_mesh_compression), libpng and libjpeg-turbo (images) and TBB (their
# parallel decode) are linked from Debian's builds, not instrumented.
for target in gltf_loader_fuzz gltf_image_fuzz; do
  "$CXX" -fsanitize=fuzzer $SAN "$OUT"/*.o "$OUT/main/$target.o" -ldraco -lpng16 \
    -lturbojpeg -ltbb -o "$OUT/$target"
  echo "$OUT/$target"
done
