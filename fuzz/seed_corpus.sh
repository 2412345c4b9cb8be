#!/usr/bin/env bash
# Fills DIR with the seed corpus: the shipped scenes and Debian's glTF2 sample files (.gltf and
# .glb up to 256 KiB each, so that the fuzzer's maximum input length stays practical). Inputs
# whose external buffers or images do not sit next to them in the fuzzer's temp folder still
# exercise everything up to the missing-file check.
#   bash fuzz/seed_corpus.sh DIR
set -euo pipefail
SRC=$(cd "$(dirname "$0")/.." && pwd)
DIR=${1:?usage: seed_corpus.sh DIR}
mkdir -p "$DIR"
i=0
while IFS= read -r -d '' f; do
  cp "$f" "$DIR/seed_$(printf %03d $i)_$(basename "$f")"
  i=$((i + 1))
done < <(find "$SRC/scenes" /usr/share/assimp/models/glTF2 \( -name '*.gltf' -o -name '*.glb' \) \
           -size -256k -print0 2>/dev/null | sort -z)
echo "$i seed files in $DIR"
