#!/usr/bin/env bash
# Runs every libFuzzer target for a while and fails if any finds a crash,
# a leak, a timeout or an out-of-memory.
#   usage: fuzz/run.sh BUILD_DIR SECONDS
# BUILD_DIR is a build configured with -DJND_FUZZ=ON (make fuzz-build). Each
# target starts from its seeds in fuzz/corpus/<target>/ (copied, so the
# repository is never written to), with the dictionary fuzz/<target>.dict;
# inputs that fail are kept in BUILD_DIR/fuzz-artifacts/ to replay with `BUILD_DIR/fuzz/fuzz_<target> FILE`.
set -uo pipefail

if [ $# -lt 1 ]; then
  echo "usage: $0 BUILD_DIR [SECONDS]" >&2
  exit 2
fi
build=$(cd "$1" && pwd) || exit 2
seconds=${2:-20}
here=$(cd "$(dirname "$0")" && pwd)
targets=${FUZZ_TARGETS:-"png jpeg hdr exr csv gltf cameras calibration manifest_csv manifest_json csf_data gaze_table gaze_data gaze_params"}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
artifacts=$build/fuzz-artifacts
mkdir -p "$artifacts"

# one target per core at a time: each still fuzzes for SECONDS on one core
# (libFuzzer runs one thread), and the 14 targets take 14·SECONDS/cores
jobs=${FUZZ_JOBS:-$(nproc)}

fuzz_one() {
  local t=$1 bin=$build/fuzz/fuzz_$1
  if [ ! -x "$bin" ]; then
    echo "fuzz: $bin is missing (configure with -DJND_FUZZ=ON -DCMAKE_C_COMPILER=clang)" >"$work/$t.result"
    return 1
  fi
  local corpus=$work/corpus-$t
  mkdir -p "$corpus"
  cp "$here/corpus/$t/"* "$corpus/" 2>/dev/null || true
  local dict=()
  [ -f "$here/$t.dict" ] && dict=(-dict="$here/$t.dict")
  local log=$work/$t.log
  # -rss_limit_mb also caps single allocations (malloc_limit_mb defaults to it)
  ASAN_OPTIONS=detect_leaks=1:allocator_may_return_null=1:intercept_tls_get_addr=0 \
  UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 \
    "$bin" -max_total_time="$seconds" -rss_limit_mb=2048 -timeout=20 -max_len=65536 \
      -print_final_stats=1 -artifact_prefix="$artifacts/$t-" ${dict[@]+"${dict[@]}"} "$corpus" >"$log" 2>&1
  local rc=$?
  local runs
  runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$')
  if [ $rc -ne 0 ]; then
    { echo "fuzz_$t: FAILED after ${runs:-?} runs (exit $rc); inputs in $artifacts"
      grep -E 'ERROR|SUMMARY|==[0-9]+==|#[0-9]+ 0x' "$log" | head -30; } >"$work/$t.result"
    return 1
  fi
  echo "fuzz_$t: ok, ${runs:-?} runs in ${seconds}s" >"$work/$t.result"
}

declare -A pid_of=()
failed=()
reap() {  # waits for one running target, prints its result
  local done_pid t
  wait -n -p done_pid
  for t in "${!pid_of[@]}"; do
    [ "${pid_of[$t]}" = "$done_pid" ] || continue
    unset "pid_of[$t]"
    if grep -q "^fuzz_$t: ok" "$work/$t.result"; then cat "$work/$t.result"
    else cat "$work/$t.result" >&2; failed+=("$t"); fi
  done
}
for t in $targets; do
  while [ ${#pid_of[@]} -ge "$jobs" ]; do reap; done
  fuzz_one "$t" &
  pid_of[$t]=$!
done
while [ ${#pid_of[@]} -gt 0 ]; do reap; done

if [ ${#failed[@]} -ne 0 ]; then
  echo "fuzz: failures in: ${failed[*]}" >&2
  exit 1
fi
