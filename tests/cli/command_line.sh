#!/usr/bin/env bash
# The command line helps: typos get the nearest name, `prism help` works, every command takes
# -q and -v, developer options stand apart in --help, render and compare spell their options
# alike, and misleading messages say what is wrong and what is allowed.
# Usage: command_line.sh PRISM SOURCE_DIR
source "$(dirname "$0")/lib/common.bash" "$@"

SCENE="$SRC/scenes/spheres.gltf"  # one camera, 'main'; one unnamed scene
BOX=/usr/share/assimp/models/glTF2/BoxTextured-glTF/BoxTextured.gltf  # no camera

# Typos: the nearest of the command's own names.
expect 2 "unknown command 'rendr'; did you mean render\?" -- rendr "$SCENE"
expect 2 "unknown command 'inof'; did you mean info\?" -- inof "$SCENE"
expect 2 "unknown command 'frobnicate' \(commands: render, " -- frobnicate
expect 2 "render: unknown option --sp; did you mean --spp\?" -- render "$SCENE" -o "$TMP/a.exr" --sp 4
expect 2 "render: unknown option --intgrator; did you mean --integrator\?" -- render "$SCENE" -o "$TMP/a.exr" --intgrator=phong
expect 2 "compare: unknown option --integrater; did you mean --integrator\?" -- compare "$SCENE" -o "$TMP/c" --integrater phong
expect 2 "info: unknown option --timign; did you mean --timing\?" -- info "$SCENE" --timign
expect 2 "render: unknown option --frobnicate \(see prism render --help\)" -- render "$SCENE" -o "$TMP/a.exr" --frobnicate
expect 2 "a command is required: render, diff, compare, info, batch, boids, help" --

# prism help and prism help COMMAND.
"$PRISM" help >"$TMP/help" || fail "prism help exited $?"
grep -q "^  render  *Render a glTF scene" "$TMP/help" || fail "prism help lists no render: $(cat "$TMP/help")"
"$PRISM" help render >"$TMP/help" || fail "prism help render exited $?"
grep -q "^Usage: prism render" "$TMP/help" || fail "prism help render: $(head -3 "$TMP/help")"
cmp -s "$TMP/help" <("$PRISM" render --help) || fail "prism help render differs from prism render --help"
expect 2 "help: unknown command 'rendr'; did you mean render\?" -- help rendr

# -q and -v on every command; developer options under their own heading.
for command in render diff compare info batch boids; do
  "$PRISM" "$command" --help >"$TMP/help"
  grep -q -- "-q,--quiet" "$TMP/help" || fail "$command --help has no -q,--quiet"
  grep -q -- "-v,--verbose" "$TMP/help" || fail "$command --help has no -v,--verbose"
done
"$PRISM" render --help >"$TMP/help"
developer=$(sed -n '/^Developer options:/,$p' "$TMP/help")
for option in --robust --build-quality --general-path; do
  grep -q -- "^  $option" <<<"$developer" || fail "render --help: $option not under Developer options"
done
grep -q -- "^  --spp" <<<"$developer" && fail "render --help: --spp among the developer options"

# info -q prints nothing for a good file and exits 1 for a bad one.
[[ -z "$("$PRISM" info -q "$SCENE" 2>&1)" ]] || fail "info -q printed something"
expect 1 "no-such.gltf" -- info -q "$TMP/no-such.gltf"
# info -v includes the timing line.
"$PRISM" info -v "$SCENE" | grep -q "^timing: load" || fail "info -v has no timing line"

# One spelling for render and compare: --integrator takes one (render) or a list (compare),
# compare keeps --integrators; render refuses a list in one line.
expect 2 "^prism: error: --integrator pathtracer: expected " -- compare "$SCENE" -o "$TMP/c" --integrator pathtracer
expect 2 "^prism: error: --integrator pathtracer: expected " -- compare "$SCENE" -o "$TMP/c" --integrators phong,pathtracer
expect 2 "^prism: error: --integrator phong,shadow: render takes one integrator \(prism compare takes a list\)" -- render "$SCENE" -o "$TMP/a.exr" --integrator phong,shadow
expect 2 "^prism: error: --target-error 0.1: given twice" -- compare "$SCENE" -o "$TMP/c" --target-error 0.1,0.1

# Whole numbers: said so, with the range allowed.
expect 2 "^prism: error: --spp: must be a whole number from 1 to 65536, not 1.5" -- render "$SCENE" -o "$TMP/a.exr" --spp 1.5
expect 2 "^prism: error: --spp: must be a whole number from 1 to 65536, not 0" -- render "$SCENE" -o "$TMP/a.exr" --spp 0
expect 2 "^prism: error: --threads: must be a whole number from 0 to 1024, not 2.5" -- render "$SCENE" -o "$TMP/a.exr" --threads 2.5
expect 2 "^prism: error: --spp: must be a whole number from 1 to 65536, not 4x" -- compare "$SCENE" -o "$TMP/c" --spp 1,4x

# Cameras and scenes that do not exist: what the file has, and what may be asked for.
expect 2 "^prism: error: --camera 5: .*BoxTextured.gltf has no cameras; leave --camera out for the default one that frames the scene, or use --camera auto$" -- render "$BOX" -o "$TMP/a.exr" --camera 5
expect 2 "^prism: error: --camera 7: .*spheres.gltf has no such camera; it has 1 camera: 0 'main' \(a name or an index\), or use auto$" -- render "$SCENE" -o "$TMP/a.exr" --camera 7
expect 2 "^prism: error: --scene 3: .*BoxTextured.gltf: scenes: no scene '3' \(the file has 1 scene: 0 \(unnamed\); give a name or an index 0\)$" -- render "$BOX" -o "$TMP/a.exr" --scene 3

[[ -e "$TMP/a.exr" || -e "$TMP/c" ]] && fail "a refused command wrote its output"
# A parameter two integrators share says each one's range and default.
"$PRISM" render --help >"$TMP/help" 2>&1
grep -qE -- "--max-depth INT .*\(whitted: 0 to 64, default 5; path: 0 to 1024, default 16\)" "$TMP/help" &&
  echo "ok: --max-depth's help gives whitted's and path's ranges" ||
  fail "--max-depth's help: $(grep -- --max-depth "$TMP/help")"

echo "$failures failed"
[[ $failures -eq 0 ]]
