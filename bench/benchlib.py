"""What the bench/ scripts share: the source root and the prism binary they run."""
import os
import sys

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
