#!/usr/bin/env bash
# Fills DIR with a seed corpus.
#   bash fuzz/seed_corpus.sh DIR            the loader's: the shipped scenes and Debian's glTF2
#                                            sample files (.gltf and .glb up to 256 KiB each, so
#                                            that the fuzzer's maximum input length stays
#                                            practical). Inputs whose external buffers or images
#                                            do not sit next to them in the fuzzer's temp folder
#                                            still exercise everything up to the missing-file check.
#   bash fuzz/seed_corpus.sh --images DIR   the image target's: a small image in every format
#                                            OpenImageIO writes (oiiotool), plus hand-made headers
#                                            of formats it only reads (DDS, a DDS volume, Cineon,
#                                            PSD, Softimage) and a progressive JPEG.
set -euo pipefail
SRC=$(cd "$(dirname "$0")/.." && pwd)
if [[ ${1:-} == --images ]]; then
  DIR=${2:?usage: seed_corpus.sh --images DIR}
  mkdir -p "$DIR"
  # Every output format of `oiiotool --help` that writes from a plain RGB(A) image.
  for ext in png jpg tif exr hdr bmp tga iff dpx pnm pgm ppm sgi ico webp gif fits rla jp2 j2k heic zfile; do
    oiiotool --pattern checker:width=4:height=4 16x12 3 -o "$DIR/seed.$ext" >/dev/null 2>&1 ||
      echo "seed_corpus.sh: oiiotool cannot write .$ext (skipped)" >&2
  done
  oiiotool --pattern fill:color=0.2,0.4,0.6,0.8 8x8 4 -o "$DIR/seed_rgba.png" >/dev/null 2>&1
  oiiotool --pattern fill:color=0.5 8x8 1 -d uint16 -o "$DIR/seed_grey16.png" >/dev/null 2>&1
  oiiotool --pattern checker 32x32 3 --attrib jpeg:progressive 1 -o "$DIR/seed_progressive.jpg" \
    >/dev/null 2>&1
  /usr/bin/python3 - "$DIR" <<'PY'
import struct, sys
d = sys.argv[1]
def dds(depth):
    # DDS_HEADER: size 124, flags CAPS|HEIGHT|WIDTH|PIXELFORMAT (|DEPTH), 4x4, uncompressed RGBA.
    flags = 0x1 | 0x2 | 0x4 | 0x1000 | (0x800000 if depth > 1 else 0)
    pf = struct.pack('<II4sIIIII', 32, 0x41, b'\0\0\0\0', 32, 0xFF0000, 0xFF00, 0xFF, 0xFF000000)
    caps2 = 0x200000 if depth > 1 else 0
    hdr = struct.pack('<IIIIIII', 124, flags, 4, 4, 16, depth, 1) + b'\0' * 44 + pf
    hdr += struct.pack('<IIIII', 0x1000, caps2, 0, 0, 0)
    return b'DDS ' + hdr + bytes(range(256)) * depth
open(f'{d}/seed.dds', 'wb').write(dds(1))
open(f'{d}/seed_volume.dds', 'wb').write(dds(4))
# Cineon: magic 0x802A5FD7 and a generic header; PSD: "8BPS" version 1; Softimage PIC magic.
open(f'{d}/seed.cin', 'wb').write(struct.pack('>IIIII', 0x802A5FD7, 2048, 1024, 0, 0) + bytes(2048))
open(f'{d}/seed.psd', 'wb').write(b'8BPS' + struct.pack('>H6xHIIHH', 1, 3, 4, 4, 8, 3) + bytes(64))
open(f'{d}/seed.pic', 'wb').write(struct.pack('>I', 0x5380F634) + bytes(200))
PY
  find "$DIR" -type f -empty -delete  # a writer that produced nothing
  echo "$(ls "$DIR" | wc -l) seed files in $DIR"
  exit 0
fi
DIR=${1:?usage: seed_corpus.sh DIR | --images DIR}
mkdir -p "$DIR"
i=0
while IFS= read -r -d '' f; do
  cp "$f" "$DIR/seed_$(printf %03d $i)_$(basename "$f")"
  i=$((i + 1))
done < <(find "$SRC/scenes" /usr/share/assimp/models/glTF2 \( -name '*.gltf' -o -name '*.glb' \) \
           -size -256k -print0 2>/dev/null | sort -z)
echo "$i seed files in $DIR"
