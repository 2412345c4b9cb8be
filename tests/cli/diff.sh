#!/usr/bin/env bash
# `prism diff` against OpenImageIO's idiff on the same images (RMSE, PSNR, maximum error and
# where it is, to the six digits both print), its exit codes, and `prism render --reference`.
# Usage: diff.sh PRISM SOURCE_DIR
source "$(dirname "$0")/lib/common.bash" "$@"

# Six significant digits on both sides: equal within one unit of the last digit.
agree() { awk -v a="$1" -v b="$2" 'BEGIN { d = a - b; if (d < 0) d = -d; m = (b < 0 ? -b : b);
  exit !(d <= 1e-5 * m + 1e-12) }'; }

# Compares prism diff with idiff -v on A vs B (idiff sees the files given as IA, IB, e.g.
# without alpha, which prism leaves out of its metrics).
compare_with_idiff() {
  local a=$1 b=$2 ia=$3 ib=$4 label=$5
  local out rms psnr max where prism_rms prism_psnr prism_max prism_where
  out=$(idiff -v "$ia" "$ib" 2>&1)
  rms=$(sed -n 's/^ *RMS error = \([^ ]*\).*/\1/p' <<<"$out")
  psnr=$(sed -n 's/^ *Peak SNR = \([^ ]*\).*/\1/p' <<<"$out")
  max=$(sed -n 's/^ *Max error *= \([^ ]*\) @.*/\1/p' <<<"$out")
  where=$(sed -n 's/^ *Max error *= [^ ]* @ \(([^)]*)\).*/\1/p' <<<"$out")
  [[ -n $rms && -n $psnr && -n $max ]] || { fail "$label: cannot read idiff's output: $out"; return; }
  prism_rms=$("$PRISM" diff "$a" "$b" --metric rmse) || fail "$label: prism diff --metric rmse"
  prism_psnr=$("$PRISM" diff "$a" "$b" --metric psnr) || fail "$label: prism diff --metric psnr"
  prism_max=$("$PRISM" diff "$a" "$b" --metric max) || fail "$label: prism diff --metric max"
  prism_where=$("$PRISM" diff "$a" "$b" | sed -n 's/^RGB .*\(([^)]*)\)$/\1/p')
  echo "$label: RMSE idiff $rms prism $prism_rms; PSNR idiff $psnr prism $prism_psnr" \
    "(peak 1); max idiff $max $where prism $prism_max $prism_where"
  agree "$prism_rms" "$rms" || fail "$label: RMSE $prism_rms, idiff $rms"
  # idiff's PSNR peak is the largest value in either image, or 1 if that is smaller; prism's
  # is always 1. The two agree once that difference is added back.
  local peak shifted
  peak=$(oiiotool --stats "$ia" "$ib" | awk '/Stats Max:/ { for (i = 3; i <= NF; ++i)
    if ($i + 0 > m) m = $i + 0 } END { print (m > 1 ? m : 1) }')
  shifted=$(awk -v p="$prism_psnr" -v m="$peak" 'BEGIN { printf "%.6g", p + 20 * log(m) / log(10) }')
  agree "$shifted" "$psnr" || fail "$label: PSNR $prism_psnr (+ peak $peak: $shifted), idiff $psnr"
  agree "$prism_max" "$max" || fail "$label: max error $prism_max, idiff $max"
  [[ "$prism_where" == "$where" ]] || fail "$label: max error at $prism_where, idiff at $where"
}

# Uniform noise against noise, and a checker against the same checker with a little noise.
for seed in 1 2 3; do
  oiiotool --pattern noise:type=uniform:min=0:max=1:seed=$seed 64x48 3 -o "$TMP/n$seed.exr"
done
compare_with_idiff "$TMP/n1.exr" "$TMP/n2.exr" "$TMP/n1.exr" "$TMP/n2.exr" "noise 1 vs 2"
compare_with_idiff "$TMP/n3.exr" "$TMP/n1.exr" "$TMP/n3.exr" "$TMP/n1.exr" "noise 3 vs 1"
oiiotool --pattern checker:width=8:height=8:color1=0.1,0.2,0.3:color2=4,2,1 64x48 3 \
  -o "$TMP/checker.exr"
oiiotool "$TMP/checker.exr" --noise:type=gaussian:mean=0:stddev=0.01:seed=7 -o "$TMP/noisy.exr"
compare_with_idiff "$TMP/noisy.exr" "$TMP/checker.exr" "$TMP/noisy.exr" "$TMP/checker.exr" \
  "checker + noise"

# Two renders: phong and shadow share their alpha at 1 spp, so idiff on RGB alone sees
# what prism compares.
SCENE="$SRC/scenes/spheres.gltf"
for integrator in phong shadow; do
  "$PRISM" render "$SCENE" -o "$TMP/$integrator.exr" --integrator "$integrator" --res 96x54 \
    --quiet || fail "render $integrator"
  oiiotool "$TMP/$integrator.exr" --ch R,G,B -o "$TMP/$integrator-rgb.exr"
done
compare_with_idiff "$TMP/phong.exr" "$TMP/shadow.exr" "$TMP/phong-rgb.exr" "$TMP/shadow-rgb.exr" \
  "phong vs shadow render"

# Exit codes and the one-number form.
a=$TMP/n1.exr b=$TMP/n2.exr
"$PRISM" diff "$a" "$a" >"$TMP/out" || fail "identical images: exit $?"
grep -q "^RGB .* 0 .* inf " "$TMP/out" || fail "identical images: table $(cat "$TMP/out")"
[[ $("$PRISM" diff "$a" "$a" --metric psnr) == inf ]] || fail "identical images: PSNR not inf"
rms=$("$PRISM" diff "$a" "$b" --metric rmse)
"$PRISM" diff "$a" "$b" --fail-above 1 >/dev/null || fail "RMSE $rms failed --fail-above 1"
"$PRISM" diff "$a" "$b" --fail-above 0.01 >/dev/null 2>"$TMP/err"
[[ $? -eq 1 ]] || fail "RMSE $rms passed --fail-above 0.01"
grep -q "rmse $rms is above --fail-above 0.01" "$TMP/err" || fail "fail message: $(cat "$TMP/err")"
"$PRISM" diff "$a" "$b" --metric psnr --fail-above 5 >/dev/null || fail "PSNR above 5 failed"
"$PRISM" diff "$a" "$b" --metric psnr --fail-above 40 >/dev/null 2>&1
[[ $? -eq 1 ]] || fail "PSNR below 40 passed --fail-above 40"
"$PRISM" diff "$a" "$b" --metric max --fail-above 0.5 >/dev/null 2>&1
[[ $? -eq 1 ]] || fail "max error of uniform noise passed --fail-above 0.5"
"$PRISM" diff "$a" "$TMP/missing.exr" 2>"$TMP/err"
[[ $? -eq 2 ]] || fail "missing file: exit not 2"
[[ $(cat "$TMP/err") == "prism: error: $TMP/missing.exr: no such file" ]] ||
  fail "missing file message: $(cat "$TMP/err")"
"$PRISM" diff "$a" "$TMP/phong.exr" 2>"$TMP/err"
[[ $? -eq 2 ]] || fail "different sizes: exit not 2"
grep -q "is 64x48 but .*phong.exr is 96x54" "$TMP/err" || fail "sizes message: $(cat "$TMP/err")"
"$PRISM" diff "$a" "$b" --metric mse 2>/dev/null
[[ $? -eq 2 ]] || fail "--metric mse accepted"

# render --reference: same pixels as without, one log line per pass, the last one in the
# metadata and equal to what prism diff says of the written file.
"$PRISM" render "$SCENE" -o "$TMP/ref.exr" --res 64x36 --spp 32 --quiet || fail "reference render"
"$PRISM" render "$SCENE" -o "$TMP/plain.exr" --res 64x36 --spp 5 --quiet || fail "plain render"
"$PRISM" render "$SCENE" -o "$TMP/passes.exr" --res 64x36 --spp 5 --reference "$TMP/ref.exr" \
  >"$TMP/stdout" 2>"$TMP/stderr" || fail "render --reference"
idiff -fail 0 -failpercent 0 -warn 0 "$TMP/plain.exr" "$TMP/passes.exr" >/dev/null ||
  fail "--reference changed the image"
[[ $(grep -c "^prism: pass [1-5]/5: RMSE [0-9.e+-]* relMSE [0-9.e+-]*$" "$TMP/stderr") -eq 5 ]] ||
  fail "expected 5 pass lines: $(cat "$TMP/stderr")"
info=$(iinfo -v "$TMP/passes.exr")
final=$(sed -n 's/^ *prism:referenceRMSE: "\(.*\)"/\1/p' <<<"$info")
per_pass=$(sed -n 's/^ *prism:referenceRMSEPerPass: "\(.*\)"/\1/p' <<<"$info")
final_rel=$(sed -n 's/^ *prism:referenceRelMSE: "\(.*\)"/\1/p' <<<"$info")
[[ $(tr ',' '\n' <<<"$per_pass" | wc -l) -eq 5 ]] || fail "per-pass RMSE list: '$per_pass'"
[[ ${per_pass##*,} == "$final" ]] || fail "last per-pass RMSE ${per_pass##*,} != final $final"
[[ $("$PRISM" diff "$TMP/passes.exr" "$TMP/ref.exr" --metric rmse) == "$final" ]] ||
  fail "metadata RMSE $final differs from prism diff"
[[ $("$PRISM" diff "$TMP/passes.exr" "$TMP/ref.exr" --metric relmse) == "$final_rel" ]] ||
  fail "metadata relMSE $final_rel differs from prism diff"
grep -q "^discarded    0 non-finite samples$" "$TMP/stdout" || fail "summary lacks discards"
grep -qF 'prism:discardedSamples: "0"' <<<"$info" || fail "EXR lacks prism:discardedSamples"
"$PRISM" render "$SCENE" -o "$TMP/quiet.exr" --res 64x36 --spp 2 --reference "$TMP/ref.exr" \
  --quiet 2>"$TMP/stderr" || fail "render --reference --quiet"
[[ -s "$TMP/stderr" ]] && fail "--quiet still logged: $(cat "$TMP/stderr")"
"$PRISM" render "$SCENE" -o "$TMP/wrong.exr" --res 65x36 --reference "$TMP/ref.exr" 2>"$TMP/err"
[[ $? -eq 2 ]] || fail "reference of another size: exit not 2"
[[ $(wc -l <"$TMP/err") -eq 1 ]] && grep -q "ref.exr is 64x36 but the render is 65x36" "$TMP/err" ||
  fail "reference size message: $(cat "$TMP/err")"
[[ -e "$TMP/wrong.exr" ]] && fail "wrote an image despite the wrong reference size"

echo "$failures failed"
[[ $failures -eq 0 ]]
