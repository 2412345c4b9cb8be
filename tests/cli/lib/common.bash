# Sourced by tests/cli/*.sh with their arguments: PRISM (the binary) and SRC (the source
# tree), as CTest passes them; a scratch directory TMP removed on exit; and `fail`, which
# prints and counts a failure for the script's closing "N failed" line.
set -u
PRISM=$1
SRC=$2
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
# Under a sanitizer build (tests/CMakeLists.txt sets PRISM_SANITIZED): LeakSanitizer cannot
# run under ptrace, so a prism run under $STRACE leaves leak checking off; and
# AddressSanitizer reserves terabytes of address space for its shadow memory, so
# address_space_limit BYTES gives no ceiling there (the release build's run applies it).
if [[ -n ${PRISM_SANITIZED:-} ]]; then
  STRACE="env ASAN_OPTIONS=${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0 strace"
  address_space_limit() { :; }
else
  STRACE=strace
  address_space_limit() { echo "prlimit --as=$1"; }
fi
failures=0
fail() {
  echo "FAIL: $*"
  failures=$((failures + 1))
}

# expect CODE PATTERN -- ARGS...: runs prism (as $RUN_PREFIX prism ARGS when RUN_PREFIX is set,
# e.g. under prlimit or strace), checks the exit code, that stderr is exactly
# one line, and that it matches PATTERN.
expect() {
  local code=$1 pattern=$2
  shift 3
  ${RUN_PREFIX:-} "$PRISM" "$@" >"$TMP/out" 2>"$TMP/err"
  local got=$?
  local lines
  lines=$(wc -l <"$TMP/err")
  if [[ $got -ne $code ]]; then
    echo "FAIL: prism $* exited $got, expected $code"; cat "$TMP/err"; failures=$((failures + 1))
  elif [[ $lines -ne 1 ]]; then
    echo "FAIL: prism $* printed $lines lines on stderr, expected 1"; cat "$TMP/err"; failures=$((failures + 1))
  elif ! grep -qE -- "$pattern" "$TMP/err"; then
    echo "FAIL: prism $*: stderr does not match '$pattern':"; cat "$TMP/err"; failures=$((failures + 1))
  else
    echo "ok: prism $* -> $got: $(cat "$TMP/err")"
  fi
}
