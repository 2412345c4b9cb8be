# Sourced by tests/cli/*.sh with their arguments: PRISM (the binary) and SRC (the source
# tree), as CTest passes them; a scratch directory TMP removed on exit; and `fail`, which
# prints and counts a failure for the script's closing "N failed" line.
set -u
PRISM=$1
SRC=$2
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
failures=0
fail() {
  echo "FAIL: $*"
  failures=$((failures + 1))
}
