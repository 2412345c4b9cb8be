#!/usr/bin/python3
"""How right the progress line's ETA is: runs `prism render` under a pseudo-terminal (so the
bar is drawn), reads every line as it comes, and compares the ETA shown when a fifth, half and
four fifths of the tiles were done with the time the render then really took to finish (the
moment the bar reached 100 %). Prints a Markdown table: ETA shown, time that was left, and the
error as a fraction of the time left.

    /usr/bin/python3 bench/eta_accuracy.py [--prism PATH] [--vs PATH] -- RENDER-ARGS...

With --vs, the same render by a second binary runs after the first, for a before/after.
"""
import argparse
import os
import pty
import re
import select
import subprocess
import sys
import time

from benchlib import find_prism

LINE = re.compile(r"(\d+)/(\d+) tiles .* ETA (\?|[0-9hms.]+)")


def seconds(text):
    """'12.3s', '4m05s', '2h13m' -> seconds."""
    m = re.fullmatch(r"(?:(\d+)h)?(?:(\d+)m)?(?:([\d.]+)s)?", text)
    if not m:
        raise ValueError(text)
    h, mins, s = m.groups()
    return int(h or 0) * 3600 + int(mins or 0) * 60 + float(s or 0)


def run(prism, args):
    """[(time since start, tiles done, total, eta seconds or None)], and when the bar hit 100 %."""
    master, slave = pty.openpty()
    start = time.monotonic()
    proc = subprocess.Popen([prism, "render", *args], stdin=subprocess.DEVNULL,
                            stdout=subprocess.DEVNULL, stderr=slave, close_fds=True)
    os.close(slave)
    seen, buffer, finished = [], b"", None
    while True:
        ready, _, _ = select.select([master], [], [], 0.5)
        if ready:
            try:
                chunk = os.read(master, 4096)
            except OSError:
                break
            if not chunk:
                break
            now = time.monotonic() - start
            buffer += chunk
            *lines, buffer = re.split(rb"[\r\n]", buffer)
            for raw in lines:
                m = LINE.search(raw.decode("utf-8", "replace"))
                if not m:
                    continue
                done, total = int(m.group(1)), int(m.group(2))
                eta = None if m.group(3) == "?" else seconds(m.group(3))
                seen.append((now, done, total, eta))
                if total > 0 and done == total and finished is None:
                    finished = now
        elif proc.poll() is not None:
            break
    proc.wait()
    os.close(master)
    if proc.returncode != 0:
        sys.exit("prism exited %d" % proc.returncode)
    return seen, finished


def report(label, seen, finished):
    print("\n%s: render took %.1f s (to the bar's 100 %%)\n" % (label, finished))
    print("| tiles done | at | ETA shown | time left | error |")
    print("| ---: | ---: | ---: | ---: | ---: |")
    worst = 0.0
    for share in (0.2, 0.5, 0.8):
        line = next((s for s in seen if s[2] and s[1] >= share * s[2] and s[3] is not None), None)
        if line is None:
            continue
        at, done, total, eta = line
        left = finished - at
        error = (eta - left) / left
        worst = max(worst, abs(error))
        print("| %d %% | %.1f s | %.1f s | %.1f s | %+.1f %% |" %
              (round(100 * done / total), at, eta, left, 100 * error))
    return worst


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--prism", default=None)
    parser.add_argument("--vs", default=None, help="a second prism binary to run the same render")
    parser.add_argument("args", nargs="+")
    a = parser.parse_args()
    binaries = [("this build", a.prism or find_prism(sys.argv[0]))]
    if a.vs:
        binaries.append(("--vs " + a.vs, a.vs))
    print("prism render " + " ".join(a.args))
    for label, prism in binaries:
        seen, finished = run(prism, a.args)
        worst = report(label, seen, finished)
        print("\nworst: %.1f %% of the time left" % (100 * worst))


if __name__ == "__main__":
    main()
