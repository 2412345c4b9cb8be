#!/usr/bin/env bash
# One frame over MPI ranks (distributed/, docs/batch.md): `mpirun -n R prism render` gives
# the single process's pixels bit for bit, with 1 or 2 threads a rank, rank 0 alone prints
# the summary, the ray counts are the frame's, adaptive sampling under several ranks is a
# one-line usage error, and a plain `prism render` never starts MPI. Skipped (exit 77) when
# prism was built without MPI.
# Usage: mpi.sh PRISM SOURCE_DIR
source "$(dirname "$0")/lib/common.bash" "$@"
# MPI's calls are in a module beside the build's executables (distributed/mpi_module.h).
MODULE="$(dirname "$PRISM")/../lib/prism/libprism_mpi.so"
if [[ ! -f $MODULE ]]; then
  echo "SKIP: $PRISM was built without MPI (find_package(MPI) found none)"
  exit 77
fi
command -v mpirun >/dev/null || { echo "FAIL: prism has an MPI module but mpirun is not on PATH"; exit 1; }
# Root in CI containers, and more ranks than cores on a 2-core machine.
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
MPIRUN=(mpirun --oversubscribe)
SCENE="$SRC/scenes/whitted.gltf"
# 320x240 in 16-pixel tiles is 300 tiles, enough for both ranks to claim many.
ARGS=(--spp 4 --res 320x240)

# Every channel of every pixel, as text: the same file contents means the same bits.
dump() { oiiotool "$1" --dumpdata 2>&1 | sed 1d; }
same_pixels() {
  local max
  max=$("$PRISM" diff "$1" "$2" --metric max) || { fail "$3: prism diff failed"; return; }
  [[ $max == 0 ]] || fail "$3: max error $max against one process"
  cmp -s <(dump "$1") <(dump "$2") || fail "$3: pixels (alpha included) differ from one process"
}

"$PRISM" render "$SCENE" -o "$TMP/one.exr" "${ARGS[@]}" >"$TMP/one.out" 2>&1 ||
  fail "single process did not render: $(cat "$TMP/one.out")"
rays_one=$(grep '^rays  ' "$TMP/one.out")

for run in "2 2" "2 1" "3 1"; do
  read -r ranks threads <<<"$run"
  label="$ranks ranks, --threads $threads"
  "${MPIRUN[@]}" -n "$ranks" "$PRISM" render "$SCENE" -o "$TMP/mpi-$ranks-$threads.exr" \
    "${ARGS[@]}" --threads "$threads" --verbose >"$TMP/mpi.out" 2>"$TMP/mpi.err" ||
    { fail "$label did not render: $(cat "$TMP/mpi.err")"; continue; }
  same_pixels "$TMP/one.exr" "$TMP/mpi-$ranks-$threads.exr" "$label"
  [[ $(grep -c '^rendered ' "$TMP/mpi.out") -eq 1 ]] || fail "$label: not exactly one summary"
  [[ $(grep '^rays  ' "$TMP/mpi.out") == "$rays_one" ]] ||
    fail "$label: rays '$(grep '^rays  ' "$TMP/mpi.out")', one process '$rays_one'"
  split=$(grep "MPI ranks rendered" "$TMP/mpi.err")
  [[ -n $split ]] || fail "$label: --verbose does not describe the split: $(cat "$TMP/mpi.err")"
  echo "ok: $label: $split"
  # One node, no transport named: shared memory, not OpenMPI's probe of UCX's transports.
  grep -q "^prism: MPI transport: shared memory" "$TMP/mpi.err" ||
    fail "$label: not shared memory on one node: $(grep 'MPI transport' "$TMP/mpi.err")"
  # The tiles the ranks rendered add up to the frame's 300.
  sum=$(sed -n 's/.*ranks rendered \([0-9 +,]*\) tiles.*/\1/p' <<<"$split" | tr -d ',')
  sum=$((${sum:-0}))
  [[ $sum == 300 ]] || fail "$label: ranks rendered $sum tiles, expected 300"
done

# A transport the user names is kept, and gives the same pixels.
# (TCP here: this machine's OpenMPI cannot select UCX, which is why probing it first is waste.)
"${MPIRUN[@]}" --mca btl self,tcp -n 2 "$PRISM" render "$SCENE" -o "$TMP/tcp.exr" "${ARGS[@]}" \
  --threads 1 --verbose >"$TMP/out" 2>"$TMP/err" || fail "--mca btl self,tcp did not render: $(cat "$TMP/err")"
grep -q "^prism: MPI transport: MPI's default or the launcher's choice" "$TMP/err" ||
  fail "--mca btl self,tcp: $(grep 'MPI transport' "$TMP/err")"
same_pixels "$TMP/one.exr" "$TMP/tcp.exr" "--mca btl self,tcp"
echo "ok: --mca btl self,tcp kept: $(grep 'MPI transport' "$TMP/err")"

# Adaptive sampling is not split yet: one line from rank 0, exit 2.
"${MPIRUN[@]}" -n 2 "$PRISM" render "$SCENE" -o "$TMP/adaptive.exr" "${ARGS[@]}" \
  --min-spp 2 --target-error 0.05 >"$TMP/out" 2>"$TMP/err"
code=$?
errors=$(grep -c '^prism: error:' "$TMP/err")
if [[ $code -ne 2 || $errors -ne 1 ]] ||
  ! grep -q '^prism: error: --target-error 0.05: not supported with 2 MPI ranks yet$' "$TMP/err"; then
  fail "--target-error under 2 ranks: exit $code, $errors error lines: $(cat "$TMP/err")"
else
  echo "ok: --target-error under 2 ranks -> $code: $(grep '^prism: error:' "$TMP/err")"
fi
[[ -e $TMP/adaptive.exr ]] && fail "--target-error under 2 ranks wrote a file"

# Without a launcher, no MPI: OpenMPI's singleton init would exec its daemon (orted), so the
# only program a plain render runs is prism itself.
$STRACE -f -e trace=execve -o "$TMP/strace" "$PRISM" render "$SCENE" -o "$TMP/plain.exr" \
  --res 64x48 --quiet || fail "plain render under strace"
execs=$(grep -c 'execve(' "$TMP/strace")
grep -q orted "$TMP/strace" && fail "a plain render started orted: $(grep orted "$TMP/strace")"
[[ $execs -eq 1 ]] || fail "a plain render ran $execs programs: $(grep 'execve(' "$TMP/strace")"
echo "ok: a plain render ran $execs program (no orted)"
# Nor does it load libmpi: only the module links it, and only a launched process opens it.
ldd "$PRISM" | grep -q libmpi && fail "prism links libmpi: $(ldd "$PRISM" | grep libmpi)"
$STRACE -f -e trace=openat -o "$TMP/opened" "$PRISM" render "$SCENE" -o "$TMP/plain.exr" \
  --res 64x48 --quiet || fail "plain render under strace"
grep -q 'libmpi\|libprism_mpi' "$TMP/opened" &&
  fail "a plain render opened MPI: $(grep 'libmpi\|libprism_mpi' "$TMP/opened" | head -2)"
echo "ok: a plain render opened no MPI library"

# Launched by mpirun without the module: one line naming it from each rank, nothing written.
mkdir -p "$TMP/bare/bin"
cp "$PRISM" "$TMP/bare/bin/prism"
"${MPIRUN[@]}" -n 2 "$TMP/bare/bin/prism" render "$SCENE" -o "$TMP/bare.exr" "${ARGS[@]}" \
  >"$TMP/out" 2>"$TMP/err" && fail "2 ranks without the MPI module rendered"
grep -q "^prism: error: an MPI launcher started 2 ranks, but prism needs MPI, whose module .*libprism_mpi.so cannot be loaded" "$TMP/err" ||
  fail "2 ranks without the MPI module: $(cat "$TMP/err")"
[[ -e $TMP/bare.exr ]] && fail "2 ranks without the MPI module wrote a file"
echo "ok: without the module: $(grep -m1 '^prism: error:' "$TMP/err")"

# A batch over 2 ranks: the ranks claim jobs as they become free, each output is the single
# process's bit for bit, and rank 0's report has every job, run by both ranks between them.
mkdir -p "$TMP/batch-one" "$TMP/batch-mpi"
BATCH_SCENE=$(realpath "$SCENE")
for folder in batch-one batch-mpi; do
  cat >"$TMP/$folder/jobs.json" <<EOF
{"version": 1, "defaults": {"resolution": "96x72"},
 "jobs": [{"name": "w", "scene": "$BATCH_SCENE", "integrator": ["phong", "shadow", "whitted"],
           "spp": [1, 4], "output": "{integrator}-{spp}.exr"}]}
EOF
done
"$PRISM" batch "$TMP/batch-one/jobs.json" --quiet || fail "batch in one process"
"${MPIRUN[@]}" -n 2 "$PRISM" batch "$TMP/batch-mpi/jobs.json" --threads 1 --quiet \
  2>"$TMP/batch.err" || fail "batch over 2 ranks: $(cat "$TMP/batch.err")"
for exr in "$TMP"/batch-one/*.exr; do
  same_pixels "$exr" "$TMP/batch-mpi/$(basename "$exr")" "batch over 2 ranks, $(basename "$exr")"
done
ranks_used=$(/usr/bin/python3 -c '
import json, sys
report = json.load(open(sys.argv[1]))
jobs = report["jobs"]
assert len(jobs) == 6 and all(j["status"] == "rendered" for j in jobs), jobs
print(report["ranks"], len({j["rank"] for j in jobs}))' "$TMP/batch-mpi/batch-report.json") ||
  fail "batch over 2 ranks: report incomplete"
[[ $ranks_used == "2 2" ]] ||
  fail "batch over 2 ranks: ranks in the report, ranks that ran jobs: $ranks_used"
echo "ok: batch over 2 ranks: 6 outputs identical to one process; ranks, ranks used: $ranks_used"
# A rerun over 2 ranks skips every job, whichever rank claims it.
"${MPIRUN[@]}" -n 2 "$PRISM" batch "$TMP/batch-mpi/jobs.json" --threads 1 --quiet ||
  fail "batch rerun over 2 ranks"
skipped=$(/usr/bin/python3 -c '
import json, sys
print(sum(j["status"] == "skipped" for j in json.load(open(sys.argv[1]))["jobs"]))' \
  "$TMP/batch-mpi/batch-report.json")
[[ $skipped == 6 ]] || fail "batch rerun over 2 ranks skipped $skipped of 6"
echo "ok: batch rerun over 2 ranks skipped $skipped of 6"

echo "$failures failed"
[[ $failures -eq 0 ]]
