#!/usr/bin/env bash
# Hostile glTF files on the command line: each is refused with exit 1 and one line naming the
# file and the element, under an address-space ceiling (prlimit --as), and strace shows that
# nothing outside the asset's folder was opened; output temporaries never outlive a signal or
# a dead writer, and a 250-character output name works. Usage: hostile_files.sh PRISM SOURCE_DIR
source "$(dirname "$0")/lib/common.bash" "$@"

command -v strace >/dev/null || { echo "FAIL: strace is missing; run scripts/setup.sh"; exit 1; }
A="$TMP/asset"
mkdir -p "$A" "$TMP/outside"
# One triangle (36 bytes of float positions), inside the folder and as the secret outside it.
printf '\0\0\0\0\0\0\0\0\0\0\0\0\0\0\200\077\0\0\0\0\0\0\0\0\0\0\0\0\0\0\200\077\0\0\0\0' >"$A/a b.bin"
cp "$A/a b.bin" "$TMP/outside/secret.bin"
ln -s ../outside/secret.bin "$A/link.bin"
# scene NAME URI: a one-triangle scene whose buffer is URI.
scene() {
  cat >"$A/$1" <<GLTF
{"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
 "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
 "buffers": [{"byteLength": 36, "uri": "$2"}],
 "bufferViews": [{"buffer": 0, "byteLength": 36}],
 "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"}]}
GLTF
}
# Every hostile run below is capped at 1 GiB of address space (but under a sanitizer:
# lib/common.bash): what the loader is refused must be refused before it is allocated.
CEILING=$(address_space_limit $((1 << 30)))

# confined PATTERN NAME URI: `prism info` (from $TMP/outside, where tinygltf used to retry)
# refuses the scene with PATTERN, and strace saw no file opened or stat'ed outside the folder.
confined() {
  local pattern=$1 name=$2
  scene "$name" "$3"
  cd "$TMP/outside" || exit 1
  RUN_PREFIX="$STRACE -f -qq -o $TMP/trace -e trace=open,openat,stat,lstat,newfstatat,statx $CEILING" \
    expect 1 "$A/$name: buffers\[0\]\.uri: $pattern" -- info "$A/$name"
  cd - >/dev/null || exit 1
  if grep -E 'outside/|"(\./)?secret\.bin"' "$TMP/trace" | grep -v execve >"$TMP/leaks"; [[ -s $TMP/leaks ]]; then
    fail "$name: opened or stat'ed outside the asset's folder: $(head -3 "$TMP/leaks")"
  fi
}
confined 'file "a\+b\.bin" not found' plus.gltf 'a+b.bin'
confined '"a%zz/\.\./\.\./outside/secret\.bin" has an invalid percent-escape' escape.gltf 'a%zz/../../outside/secret.bin'
confined '"a%00/\.\./\.\./outside/secret\.bin" decodes to a NUL character' nul.gltf 'a%00/../../outside/secret.bin'
confined 'data: URI of media type "x" is not allowed for a buffer' data.gltf 'data:x;base64,/../../outside/secret.bin'
confined 'file "secret\.bin" not found' cwd.gltf 'secret.bin'
confined '"\.\.%2Foutside%2Fsecret\.bin" points outside the asset.s folder' dotdot.gltf '..%2Foutside%2Fsecret.bin'
# A symlink out: resolving it reads the link (readlink, lstat) but nothing outside is opened.
scene link.gltf link.bin
RUN_PREFIX="$STRACE -f -qq -o $TMP/trace -e trace=open,openat" expect 1 'buffers\[0\]\.uri: "link\.bin" points outside' -- info "$A/link.gltf"
grep -q 'secret' "$TMP/trace" && fail "link.gltf: opened $(grep secret "$TMP/trace" | head -1)"
# And what is inside is opened by its exact canonical path, without following a final symlink.
scene ok.gltf 'a%20b.bin'
$STRACE -f -qq -o "$TMP/trace" -e trace=openat "$PRISM" info "$A/ok.gltf" >/dev/null 2>&1 || fail "ok.gltf did not load"
grep -q "\"$(realpath "$A")/a b.bin\", O_RDONLY|O_NONBLOCK|O_NOFOLLOW" "$TMP/trace" ||
  fail "ok.gltf: the buffer was not opened by its canonical path with O_NOFOLLOW: $(grep 'a b' "$TMP/trace")"

# Memory: 16 primitives, each a zero-filled accessor of 3 x 2^21 vertices (72 MiB as floats, 24
# MiB of indices): 1.5 GiB together, in a 1 KB file (more than the 1 GiB ceiling below even
# for a process that maps few libraries).
{
  printf '{"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],\n'
  printf ' "accessors": [{"componentType": 5126, "count": 6291456, "type": "VEC3"}],\n "meshes": [{"primitives": ['
  for i in $(seq 0 15); do printf '%s{"attributes": {"POSITION": 0}}' "$([[ $i -gt 0 ]] && echo ,)"; done
  printf ']}]}\n'
} >"$A/bomb.gltf"
RUN_PREFIX="$CEILING" expect 1 "bomb.gltf: accessors\[0\]: needs 72.0 MiB, which takes the load past its memory budget of 256.0 MiB" -- info "$A/bomb.gltf" --memory-limit 0.25
# With the default 8 GiB budget the 1 GiB ceiling is reached first: still one line naming what
# was being allocated, never a bare std::bad_alloc.
if [[ -n $CEILING ]]; then
  RUN_PREFIX="$CEILING" expect 1 "bomb.gltf: (accessors\[0\]|meshes\[0\]\.primitives\[[0-9]+\]\.indices): out of memory \(std::bad_alloc\)" -- info "$A/bomb.gltf"
else
  echo "skipped: the bomb under the 1 GiB ceiling (no ceiling under a sanitizer)"
fi
for command in render info compare; do
  "$PRISM" "$command" --help | grep -q -- "--memory-limit" || fail "$command has no --memory-limit"
done

# Images: a DDS volume texture named .png never reaches a decoder.
/usr/bin/python3 - "$A/volume.png" <<'PY'
import struct, sys
pf = struct.pack('<II4sIIIII', 32, 0x41, b'\0\0\0\0', 32, 0xFF0000, 0xFF00, 0xFF, 0xFF000000)
hdr = struct.pack('<IIIIIII', 124, 0x801007, 4, 4, 16, 64, 1) + b'\0' * 44 + pf
hdr += struct.pack('<IIIII', 0x1000, 0x200000, 0, 0, 0)
open(sys.argv[1], 'wb').write(b'DDS ' + hdr + b'\x7f' * 4096)
PY
scene tex.gltf 'a%20b.bin'
sed -i 's/"bufferViews"/"images": [{"uri": "volume.png", "mimeType": "image\/png"}], "textures": [{"source": 0}], "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],\n "bufferViews"/; s/"POSITION": 0}/"POSITION": 0}, "material": 0/' "$A/tex.gltf"
RUN_PREFIX="$CEILING" expect 1 "tex.gltf: images\[0\]: not a PNG or JPEG image \(it starts with 44 44 53 20" -- render "$A/tex.gltf" -o "$TMP/tex.exr"
[[ -e $TMP/tex.exr ]] && fail "tex.gltf: an output was written"

# GLB cut by 4 bytes with its header's length fixed.
/usr/bin/python3 - "$A/cut.glb" <<'PY'
import json, struct, sys
doc = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
       "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}], "buffers": [{"byteLength": 36}],
       "bufferViews": [{"buffer": 0, "byteLength": 36}],
       "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"}]}
j = json.dumps(doc).encode(); j += b' ' * (-len(j) % 4)
body = struct.pack('<I4s', len(j), b'JSON') + j + struct.pack('<I4s', 36, b'BIN\0') + bytes(32)
open(sys.argv[1], 'wb').write(struct.pack('<4sII', b'glTF', 2, 12 + len(body)) + body)
PY
RUN_PREFIX="$CEILING" expect 1 "cut.glb: GLB chunk 1: length 36 at byte [0-9]+ runs 4 bytes past the end of the file" -- info "$A/cut.glb"

# Numbers: a node scale past float's range; a primitive mode past int.
scene scale.gltf 'a%20b.bin'
sed -i 's/"nodes": \[{"mesh": 0}\]/"nodes": [{"mesh": 0, "scale": [1e39, 1, 1]}]/' "$A/scale.gltf"
expect 1 "scale.gltf: nodes\[0\]: world transform is not finite as a float" -- info "$A/scale.gltf"
scene mode.gltf 'a%20b.bin'
sed -i 's/"POSITION": 0}/"POSITION": 0}, "mode": 4294967300/' "$A/mode.gltf"
expect 1 "mode.gltf: meshes\[0\]\.primitives\[0\]\.mode: expected an integer in \[0, 2\^31 - 1\], got 4294967300" -- info "$A/mode.gltf"

# Messages: an 8 MB data URI is quoted in part; a camera name's escape codes are escaped; a
# warning names the file once.
scene huge.gltf "data:$(head -c 8388608 /dev/zero | tr '\0' A);base64,AAAA"
expect 1 "huge.gltf: buffers\[0\]\.uri: data: URI of media type \"A{64}\.\.\.\" \(8388608 bytes\) is not allowed" -- info "$A/huge.gltf"
(($(wc -c <"$TMP/err") < 400)) || fail "huge.gltf: a message of $(wc -c <"$TMP/err") bytes"
scene camera.gltf 'a%20b.bin'
sed -i 's/"nodes": \[{"mesh": 0}\]/"nodes": [{"mesh": 0, "camera": 0}], "cameras": [{"name": "\\u001b[2J\\u001b[Hcam", "type": "perspective", "perspective": {"yfov": 0.5, "znear": 0.1}}], "extensionsUsed": ["EXT_unknown"]/' "$A/camera.gltf"
"$PRISM" info "$A/camera.gltf" >"$TMP/out" 2>&1 || fail "camera.gltf did not load: $(cat "$TMP/out")"
grep -q $'\x1b' "$TMP/out" && fail "camera.gltf: an escape character reached the terminal"
grep -qF '\x1B[2J\x1B[Hcam' "$TMP/out" || fail "camera.gltf: the escaped name is not shown: $(grep -i cam "$TMP/out")"
"$PRISM" render "$A/camera.gltf" -o "$TMP/camera.exr" --res 8x8 --quiet 2>"$TMP/err" >/dev/null || fail "camera.gltf did not render"
line=$(grep extensionsUsed "$TMP/err")
[[ $(grep -o "camera\.gltf" <<<"$line" | wc -l) -eq 1 ]] || fail "the warning does not name the file exactly once: $line"

# Output files. An empty scene renders fast enough that the EXR write is what takes time.
cat >"$TMP/empty.gltf" <<'GLTF'
{"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"camera": 0}],
 "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1}}]}
GLTF
mkdir -p "$TMP/outputs"
# A valid 250-character output name (the temporary name must stay within NAME_MAX too).
long="$(printf 'n%.0s' {1..246}).exr"
"$PRISM" render "$TMP/empty.gltf" -o "$TMP/outputs/$long" --res 8x8 --quiet 2>/dev/null || fail "a 250-character output name failed"
[[ -f "$TMP/outputs/$long" ]] || fail "the 250-character output was not written"
rm -f "$TMP/outputs/$long"
# Temporaries of a dead writer are removed by the next write; a live writer's are kept.
dead=$(sh -c 'echo $$')
touch "$TMP/outputs/.e.exr.tmp-$dead-0.exr" "$TMP/outputs/.e.exr.tmp-$$-0.exr"
"$PRISM" render "$TMP/empty.gltf" -o "$TMP/outputs/e.exr" --res 8x8 --quiet 2>/dev/null || fail "render e.exr"
[[ -e "$TMP/outputs/.e.exr.tmp-$dead-0.exr" ]] && fail "the dead writer's temporary is still there"
[[ -e "$TMP/outputs/.e.exr.tmp-$$-0.exr" ]] || fail "a live process's temporary was removed"
rm -f "$TMP/outputs/.e.exr.tmp-$$-0.exr" "$TMP/outputs/e.exr"
# SIGTERM while the EXR is being written: the process dies of it, leaving nothing behind.
for sig in TERM INT; do
  # A background job of a script ignores SIGINT unless told otherwise; the renderer keeps an
  # ignored signal ignored, so the default disposition is restored for it here.
  env --default-signal="$sig" "$PRISM" render "$TMP/empty.gltf" -o "$TMP/outputs/big.exr" \
    --res 2048x2048 --quiet --threads 1 2>/dev/null &
  pid=$!
  seen=0
  for _ in $(seq 4000); do
    # A non-empty temporary: the write itself, not the empty probe made and removed at once
    # when the output is checked before the render.
    if [[ -n $(find "$TMP/outputs" -name '.big.exr.tmp-*' -size +0 2>/dev/null) ]]; then
      seen=1; kill -"$sig" "$pid"; break
    fi
    kill -0 "$pid" 2>/dev/null || break
    sleep 0.002
  done
  wait "$pid"
  status=$?
  if ((seen)); then
    expected=$((128 + $(kill -l "$sig")))
    [[ $status -eq $expected ]] || fail "SIG$sig during the write: exit $status, expected $expected"
    left=$(ls -A "$TMP/outputs")
    [[ -z $left ]] && echo "ok: SIG$sig during the EXR write left nothing" || fail "SIG$sig left: $left"
  else
    fail "SIG$sig: never saw the temporary file (exit $status)"
  fi
  rm -rf "$TMP/outputs" && mkdir -p "$TMP/outputs"
done

echo "$failures failed"
[[ $failures -eq 0 ]]
