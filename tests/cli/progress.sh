#!/usr/bin/env bash
# The progress line under a pseudo-terminal 80 columns wide: it shows before the first tile
# is done, never reaches the last column (so it never wraps), gives an ETA measured from the
# tiles' throughput, and says when the image is being written. Usage: progress.sh PRISM SOURCE_DIR
source "$(dirname "$0")/lib/common.bash" "$@"

export PYTHONPATH="$(dirname "$0")/lib"
python3 - "$PRISM" "$SRC/scenes/spheres.gltf" "$TMP/p.exr" <<'PY' || fail "progress line under a pty (above)"
import re, sys
from pty_run import run
prism, scene, out = sys.argv[1:]
code, chunks = run([prism, "render", scene, "-o", out, "--res", "320x240", "--spp", "256",
                    "--threads", "1"])
text = b"".join(c for _, c in chunks).decode(errors="replace")
failures = []
if code != 0:
    failures.append("exit %d" % code)
# Each redraw starts with \r and ends by clearing the rest of the line.
segments = [s.replace("\x1b[K", "") for s in re.split(r"[\r\n]", text)]
# The progress line's redraws; the summary printed after it is not the bar.
bars = [s for s in segments if "tiles" in s]
drawn = bars + [s for s in segments if s.startswith("writing ")]
longest = max((len(s) for s in drawn), default=0)
if longest > 79:
    failures.append("a line of %d characters at 80 columns: %r" % (longest, max(drawn, key=len)))
if not bars:
    failures.append("no progress line: %r" % text[:400])
elif "0/0 tiles" not in bars[0] and " 0%" not in bars[0]:
    failures.append("the first line is not at 0%%: %r" % bars[0])
etas = [float(m.group(1)) for s in bars for m in [re.search(r"ETA ([0-9.]+)s", s)] if m]
if not etas:
    failures.append("no ETA in seconds: %r" % bars[-3:])
if not any(s.startswith("writing " + out) for s in segments):
    failures.append("no writing phase")
first_bar = next(t for t, c in chunks if b"tiles" in c) if bars else None
total = chunks[-1][0] if chunks else 0
# A measured ETA: when half the tiles are in, what is left should take about as long again.
halfway = [s for s in bars if re.search(r" (4[5-9]|5[0-5])% ", s)]
print("lines: %d, longest %d, first bar after %.2f s of %.2f s, ETAs %s, halfway %r"
      % (len(bars), longest, first_bar or -1, total, etas[:3] + etas[-3:], halfway[:1]))
for f in failures:
    print("FAIL:", f)
sys.exit(1 if failures else 0)
PY

# prism compare: a line from the start, naming the item under way (not the one before it).
XDG_CACHE_HOME="$TMP/cache" python3 - "$PRISM" "$SRC/scenes/spheres.gltf" "$TMP/report" <<'PY' || fail "compare's progress under a pty (above)"
import re, sys
from pty_run import run
prism, scene, report = sys.argv[1:]
code, chunks = run([prism, "compare", scene, "-o", report, "--res", "64x48", "--spp", "1,4",
                    "--integrator", "phong,whitted", "--reference-spp", "16"])
first = next((t for t, c in chunks if b"prism: compare" in c), None)
out = b"".join(c for _, c in chunks)
lines = [s for s in re.split(r"[\r\n]", out.decode(errors="replace").replace("\x1b[K", ""))
         if s.startswith("prism: compare ")]
failures = []
if code != 0:
    failures.append("exit %d" % code)
if first is None or first > 1.0:
    failures.append("no line within the first second (%s)" % first)
labels = []
for s in lines:
    m = re.match(r"prism: compare (\d+)/5 \d+%, ETA [^:]*: (.*)$", s)
    if m and (not labels or labels[-1] != (m.group(1), m.group(2))):
        labels.append((m.group(1), m.group(2)))
# One shared path reference, then the 2 x 2 combinations.
want = [("1", "path reference"), ("2", "phong, analytic, uniform, 1 spp"), ("3", "phong, analytic, uniform, 4 spp")]
if labels[:3] != want:
    failures.append("labels %r, expected %r first" % (labels[:4], want))
if any(len(s) > 79 for s in lines):
    failures.append("a line longer than 79 columns")
print("first line after %.2f s; labels %r" % (first or -1, labels))
for f in failures:
    print("FAIL:", f)
sys.exit(1 if failures else 0)
PY

echo "$failures failed"
[[ $failures -eq 0 ]]
