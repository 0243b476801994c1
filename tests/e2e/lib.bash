# Helpers for the end-to-end tests: source this file.
set -u
: "${JND:?JND must point at the jnd binary}"
T=${JND_TMP:-/tmp/jnd-e2e}
rm -rf "$T" && mkdir -p "$T"
fails=0
checks=0
ok() { checks=$((checks + 1)); echo "ok   $1"; }
bad() { checks=$((checks + 1)); fails=$((fails + 1)); echo "FAIL $1"; }
check() { # check NAME COMMAND...
  local name=$1; shift
  if "$@"; then ok "$name"; else bad "$name"; fi
}
# expect_exit CODE NAME COMMAND... : runs COMMAND, checks its exit status
expect_exit() {
  local want=$1 name=$2; shift 2
  "$@" >"$T/out.txt" 2>"$T/err.txt"
  local got=$?
  if [ "$got" -eq "$want" ]; then ok "$name"; else bad "$name (exit $got, wanted $want; stderr: $(head -c 300 "$T/err.txt"))"; fi
}
# the last command's stderr is one line starting with "jnd: "
one_line_error() {
  local n; n=$(wc -l <"$T/err.txt")
  [ "$n" -eq 1 ] && grep -q '^jnd: ' "$T/err.txt"
}
# skip REASON: this test cannot run here. Exits 77, which CTest reports as
# skipped; where JND_NO_SKIP is set (CI has shared data, a renderer, python3
# and the npm cache) a skip is a failure. Checks already run still count:
# a failed one fails the test.
skip() {
  echo "skip: $*"
  if [ -n "${JND_NO_SKIP:-}" ]; then bad "skipped, but JND_NO_SKIP is set"; fi
  echo "$((checks - fails)) passed, $fails failed, skipped"
  [ "$fails" -eq 0 ] && exit 77
  exit 1
}
# need_webxr_assets: sets ASSETS to the cached npm package
# @webxr-input-profiles/assets (MIT, pinned; scripts/install-deps.sh fetches
# it, bench/webxr_assets.sh); skips the test where the cache is missing
need_webxr_assets() {
  . "$(dirname "${BASH_SOURCE[0]}")/../../bench/webxr_assets.sh"
  ASSETS=$(webxr_assets) ||
    skip "@webxr-input-profiles/assets $WEBXR_ASSETS_VERSION is not in $(webxr_assets_cache) (scripts/install-deps.sh fetches it)"
}
shared_data() { [ -n "${JND_SHARED:-}" ] && [ -f "$JND_SHARED/data/README.md" ]; }
# need_renderer: skips the test where no OpenGL 4.5 core context can be had
# (jnd render then says so in one line), rather than failing every check
need_renderer() {
  local probe err
  probe=$(mktemp -d)
  if ! err=$("$JND" render builtin -o "$probe/r" --views 1 --size 16x16 --map-size 16 --quiet 2>&1); then
    rm -rf "$probe"
    case $err in
      *"OpenGL"*|*"EGL"*) skip "no OpenGL renderer: $err" ;;
      *) bad "the renderer probe failed: $err"; finish ;;
    esac
  fi
  rm -rf "$probe"
}
finish() {
  echo "$((checks - fails)) passed, $fails failed"
  [ "$fails" -eq 0 ]
  exit $?
}
