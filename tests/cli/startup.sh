#!/usr/bin/env bash
# What a process loads before it renders (docs/images.md): the executable links no
# OpenImageIO and no Draco, a textured glTF renders without loading OpenImageIO, and the
# commands that need it (a PNG given to `prism diff`) load its module and work; a plain glTF
# opens no Draco library and a Draco-compressed one loads its module; a missing module fails
# only what needs it, with one line naming the file (and the primitive, for Draco).
# Usage: startup.sh PRISM SOURCE_DIR
source "$(dirname "$0")/lib/common.bash" "$@"
BOX=/usr/share/assimp/models/glTF2/BoxTextured-glTF/BoxTextured.gltf

libs=$(ldd "$PRISM" | wc -l)
oiio=$(ldd "$PRISM" | grep -c OpenImageIO)
echo "prism links $libs shared libraries, $oiio of them OpenImageIO's"
[[ $oiio -eq 0 ]] || fail "prism links OpenImageIO: $(ldd "$PRISM" | grep OpenImageIO)"
ldd "$PRISM" | grep -q libdraco && fail "prism links Draco: $(ldd "$PRISM" | grep libdraco)"
# The OpenImageIO build pulled in about 260; what is left is Embree, TBB, OCIO, OpenEXR,
# libpng, libjpeg-turbo, Draco and their own dependencies (MPI is a module too: mpi.sh).
[[ $libs -lt 120 ]] || fail "prism links $libs shared libraries"

# A textured render (PNG texture) opens no OpenImageIO library.
$STRACE -f -e trace=openat -o "$TMP/trace" "$PRISM" render "$BOX" --res 32x24 \
  -o "$TMP/box.exr" --preview "$TMP/box.png" -q || fail "textured render failed"
opened=$(grep -c 'OpenImageIO\|libprism_oiio' "$TMP/trace")
echo "textured render: $(grep -c 'openat(' "$TMP/trace") files opened, $opened of OpenImageIO"
[[ $opened -eq 0 ]] || fail "a textured render opened OpenImageIO: $(grep OpenImageIO "$TMP/trace" | head -2)"
[[ -s $TMP/box.exr && -s $TMP/box.png ]] || fail "the render wrote no EXR or PNG"
grep -q 'draco' "$TMP/trace" && fail "a render without Draco opened it: $(grep draco "$TMP/trace" | head -2)"

# A Draco-compressed glTF loads the Draco module and renders the plain file's pixels.
DRACO=/usr/share/assimp/models/glTF2/draco/2CylinderEngine.gltf
PLAIN=/usr/share/assimp/models/glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb
$STRACE -f -e trace=openat -o "$TMP/trace3" "$PRISM" render "$DRACO" --res 32x24 \
  -o "$TMP/draco.exr" -q || fail "Draco render failed"
grep -q 'libprism_draco.so' "$TMP/trace3" || fail "a Draco render did not load the module"
"$PRISM" render "$PLAIN" --res 32x24 -o "$TMP/plain.exr" -q || fail "plain render failed"
draco_max=$("$PRISM" diff "$TMP/draco.exr" "$TMP/plain.exr" --metric rmse)
echo "Draco render: module loaded, RMSE $draco_max against the uncompressed file"
# Draco quantises positions and normals (0.0032 measured); a mis-decoded mesh is far off.
awk -v e="$draco_max" 'BEGIN { exit !(e < 0.01) }' ||
  fail "Draco render: RMSE $draco_max against the uncompressed file, expected < 0.01"

# A PNG to compare: the module is loaded, and the PNG compares equal to itself.
$STRACE -f -e trace=openat -o "$TMP/trace2" "$PRISM" diff "$TMP/box.png" "$TMP/box.png" \
  --metric rmse >"$TMP/rmse" || fail "prism diff on PNGs failed"
grep -q 'libprism_oiio.so' "$TMP/trace2" || fail "prism diff on a PNG did not load the module"
[[ $(cat "$TMP/rmse") == 0 ]] || fail "a PNG against itself: RMSE $(cat "$TMP/rmse")"
echo "prism diff of a PNG against itself: RMSE $(cat "$TMP/rmse"), module loaded"

# Without the module: EXR work still runs; a PNG comparison fails in one line naming the file.
mkdir -p "$TMP/bin" "$TMP/lib/prism"
cp "$PRISM" "$TMP/bin/prism"
PRISM="$TMP/bin/prism"
"$PRISM" diff "$TMP/box.exr" "$TMP/box.exr" --metric rmse >/dev/null 2>&1 ||
  fail "an EXR diff needed the module"
# The module's path once: the loader's own message starts with it too.
expect 2 "box.png: needs OpenImageIO, whose module [^ ]*libprism_oiio.so cannot be loaded: cannot open shared object file: No such file or directory$" -- \
  diff "$TMP/box.png" "$TMP/box.exr"
expect 1 "2CylinderEngine.gltf: meshes\[0\].primitives\[0\].extensions.KHR_draco_mesh_compression: needs Draco, whose module .*libprism_draco.so cannot be loaded" -- \
  render "$DRACO" --res 32x24 -o "$TMP/nodraco.exr"
[[ -e $TMP/nodraco.exr ]] && fail "a Draco render without the module wrote a file"
# A file under the module's name that is not Prism's module: refused in one line that reads
# on from the file that needed it, nothing loaded from it.
cp "$(ldconfig -p | awk '/libz\.so\.1 / {print $NF; exit}')" "$TMP/lib/prism/libprism_oiio.so"
expect 2 "box.png: needs OpenImageIO, whose module [^ ]*libprism_oiio.so is not Prism's$" -- \
  diff "$TMP/box.png" "$TMP/box.exr"
rm -f "$TMP/lib/prism/libprism_oiio.so"
"$PRISM" render "$PLAIN" --res 32x24 -o "$TMP/plain2.exr" -q || fail "an uncompressed render needed the Draco module"

echo "$failures failed"
[[ $failures -eq 0 ]]
