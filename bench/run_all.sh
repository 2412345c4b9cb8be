#!/usr/bin/env bash
# Runs every benchmark of docs/benchmarks.md in one session, in order, and writes the raw
# outputs to OUT (default /tmp/prism-bench-<date>):
#
#   bash bench/run_all.sh [OUT]
#
#   machine.txt     nproc, CPU model, memory, versions
#   load.txt        uptime before and after each step (the machine may be shared)
#   micro.txt       bench/micro_bench.cpp (Google Benchmark, 3 repetitions, aggregates)
#   probe.txt       bench/embree_probe_bench.cpp (raw Embree vs Prism, 1 and 2 threads)
#   probe_flat.txt  the same for the engine with every mesh placement baked (--flat)
#   macro.md        bench/macro.py (load, render, rays/s, peak RSS, error vs reference)
#   threads.md      bench/threads.py (1, 2, all threads)
#   peers.md        bench/peers/run_peers.py (Cycles, POV-Ray), about 4 minutes
#   peers.svg/png   that table plotted as time against error (bench/plot_peers.py)
#   profile.txt     callgrind instruction counts of one shadow render (if valgrind is there)
#   scenes/         the generated scenes (bench/make_bench_scenes.py), not to be committed
#
# Builds Release into build-bench/ first (PRISM_BUILD_DIR overrides). Needs what
# scripts/setup-bench.sh installs. About 6 minutes on a quiet 2-core machine.
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=${1:-/tmp/prism-bench-$(date +%Y%m%d-%H%M%S)}
BUILD=${PRISM_BUILD_DIR:-build-bench}
mkdir -p "$OUT"
OUT=$(cd "$OUT" && pwd)
ENGINE=/usr/share/assimp/models/glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb

step() {
  echo "== $1" >&2
  echo "$(date +%T) before $1: $(uptime)" >>"$OUT/load.txt"
}
done_step() {
  echo "$(date +%T) after  $1: $(uptime)" >>"$OUT/load.txt"
}

step build
PRISM_BUILD_DIR="$BUILD" bash scripts/build.sh >"$OUT/build.log" 2>&1
done_step build
export PRISM="$PWD/$BUILD/apps/prism"

{
  echo "date: $(date -Is)"
  echo "nproc: $(nproc)"
  echo "cpu: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//')"
  lscpu | grep -E '^(Architecture|Thread|Core|Socket|L[123])' || true
  free -g | head -2
  echo "uptime: $(uptime)"
  echo "kernel: $(uname -r)"
  echo "git: $(git rev-parse HEAD) $(git status --porcelain | wc -l) changed files"
  echo "embree: $(dpkg-query -W -f='${Version}' libembree3-3 2>/dev/null || echo '?')"
  echo "compiler: $(c++ --version | head -1)"
} >"$OUT/machine.txt"

step scenes
mkdir -p "$OUT/scenes"
python3 bench/make_bench_scenes.py --spheres "$OUT/scenes/sphere_field.gltf" \
  --mesh "$OUT/scenes/terrain.glb" >"$OUT/scenes.log"
done_step scenes

step micro
"$BUILD/bench/micro_bench" --benchmark_repetitions=3 --benchmark_report_aggregates_only=true \
  --benchmark_out="$OUT/micro.json" --benchmark_out_format=json >"$OUT/micro.txt" 2>&1
done_step micro

step probe
"$BUILD/bench/embree_probe_bench" --reps 5 --threads 1,2 "$ENGINE" scenes/spheres.gltf \
  "$OUT/scenes/sphere_field.gltf" >"$OUT/probe.txt" 2>&1
# The engine's 52 instances again with every placement baked into one flat BVH.
"$BUILD/bench/embree_probe_bench" --reps 5 --threads 1 --flat "$ENGINE" >"$OUT/probe_flat.txt" 2>&1
done_step probe

step macro
/usr/bin/python3 bench/macro.py --generated "$OUT/scenes" --out "$OUT/macro" >"$OUT/macro.md"
done_step macro

step threads
/usr/bin/python3 bench/threads.py --generated "$OUT/scenes" --out "$OUT/threads" \
  >"$OUT/threads.md"
done_step threads

step peers
/usr/bin/python3 bench/peers/run_peers.py --out "$OUT/peers" >"$OUT/peers.md"
# The same table as a time-against-error plot (SVG, and a PNG drawn by headless Chromium).
python3 bench/plot_peers.py "$OUT/peers.md" "$OUT/peers.svg"
chromium --headless --no-sandbox --disable-gpu --disable-quic --no-first-run \
  --disable-background-networking --disable-component-update --disable-sync \
  --user-data-dir="$(mktemp -d)" --hide-scrollbars --window-size=1620,440 \
  --screenshot="$OUT/peers.png" "file://$OUT/peers.svg" 2>/dev/null || true
done_step peers

# Where the time goes: instructions (not time, so the load does not matter) inside
# prism::render for the shadow integrator on the shipped scene, one thread.
step profile
if command -v valgrind >/dev/null && command -v callgrind_annotate >/dev/null; then
  valgrind --tool=callgrind --toggle-collect='prism::render(*' \
    --callgrind-out-file="$OUT/callgrind.out" "$PRISM" render scenes/spheres.gltf \
    -o "$OUT/callgrind.exr" --integrator shadow --spp 1 --res 427x240 --threads 1 \
    >"$OUT/callgrind.log" 2>&1
  callgrind_annotate "$OUT/callgrind.out" >"$OUT/profile.txt" 2>&1
else
  echo "valgrind not installed: no profile" >"$OUT/profile.txt"
fi
done_step profile

echo "raw outputs in $OUT" >&2
