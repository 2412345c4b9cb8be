"""What the bench/ scripts share: the source root and the prism binary they run."""
import os
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def find_prism(script):
    """$PRISM, else the benchmark build's prism, else the normal build's."""
    if os.environ.get("PRISM"):
        return os.environ["PRISM"]
    for d in ("build-bench", "build"):
        p = os.path.join(ROOT, d, "apps/prism")
        if os.path.exists(p):
            return p
    sys.exit(f"{script}: no prism binary (build it, or set $PRISM)")


def run_logged(cmd, log):
    """Runs `cmd`, keeping its command line and output in the file `log`; exits with its
    output's tail if it fails. Returns (output, wall seconds)."""
    start = time.perf_counter()
    proc = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    seconds = time.perf_counter() - start
    with open(log, "w") as f:
        f.write(" ".join(cmd) + "\n" + proc.stdout)
    if proc.returncode != 0:
        sys.exit("failed (%d): %s\n%s" % (proc.returncode, " ".join(cmd), proc.stdout[-3000:]))
    return proc.stdout, seconds
