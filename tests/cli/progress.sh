#!/usr/bin/env bash
# The progress line under a pseudo-terminal 80 columns wide: it shows before the first tile
# is done, never reaches the last column (so it never wraps), gives an ETA measured from the
# tiles' throughput, and says when the image is being written. Usage: progress.sh PRISM SOURCE_DIR
source "$(dirname "$0")/lib/common.bash" "$@"

python3 - "$PRISM" "$SRC/scenes/spheres.gltf" "$TMP/p.exr" <<'PY' || fail "progress line under a pty (above)"
import fcntl, os, pty, re, struct, sys, termios, time
prism, scene, out = sys.argv[1:]
pid, fd = pty.fork()
if pid == 0:
    os.environ["COLUMNS"] = "80"
    os.execv(prism, [prism, "render", scene, "-o", out, "--res", "320x240", "--spp", "256",
                     "--threads", "1"])
fcntl.ioctl(fd, termios.TIOCSWINSZ, struct.pack("HHHH", 24, 80, 0, 0))
start = time.monotonic()
chunks = []  # (seconds since start, bytes)
while True:
    try:
        data = os.read(fd, 65536)
    except OSError:
        break
    if not data:
        break
    chunks.append((time.monotonic() - start, data))
_, status = os.waitpid(pid, 0)
text = b"".join(c for _, c in chunks).decode(errors="replace")
failures = []
if os.waitstatus_to_exitcode(status) != 0:
    failures.append("exit %d" % os.waitstatus_to_exitcode(status))
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

echo "$failures failed"
[[ $failures -eq 0 ]]
