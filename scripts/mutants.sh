#!/usr/bin/env bash
# Mutation check of the decision-critical code: applies each one-line
# mutation of tests/mutants.txt, one at a time, to a scratch copy of the
# source (never the working tree), rebuilds it incrementally, runs the tests
# that should catch it, and reports whether the suite caught it and by which
# test. Exits 1 if a mutation survived, did not build, or is stale (its
# original text is no longer in its file).
#
#   usage: scripts/mutants.sh [--list FILE] [--only NAME,...] [--ci] [--all] [--check]
#
#   --list FILE   the mutations (default tests/mutants.txt; its header says the format)
#   --only N,...  just these entries
#   --ci          just the sections whose header line ends in "[ci]" (the
#                 subset .ci/run runs, to keep CI within its time; make
#                 mutants runs them all)
#   --all         run the whole fast suite (every test not labelled slow) on each
#                 mutation, to list every test that catches it
#   --check       only check that every entry still finds its original text
#
# By default the entry's tests run one at a time, in the order the entry
# lists them (fastest first), and the first that fails is reported; only if
# none fails does the rest of the fast suite run, and the mutation is
# reported as caught by another test or as SURVIVED. Before any mutation
# the listed tests must pass on the unmutated copy (the baseline).
#
# The scratch copy and its build live in $MUTANTS_DIR (default build-mutants/),
# kept between runs so that a run rebuilds only what changed (a build of the
# targets the tests need: the unit test's executable, or jnd for e2e). Tests
# see the real shared data folder (../shared beside the repository).
set -uo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
list=$here/tests/mutants.txt
only=""
ci=0
all=0
check_only=0
while [ $# -gt 0 ]; do
  case $1 in
    --list) list=$2; shift 2 ;;
    --only) only=",$2,"; shift 2 ;;
    --ci) ci=1; shift ;;
    --all) all=1; shift ;;
    --check) check_only=1; shift ;;
    -h|--help) sed -n '2,27p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "mutants: unknown option $1 (scripts/mutants.sh --help)" >&2; exit 2 ;;
  esac
done
[ -f "$list" ] || { echo "mutants: $list: no such file" >&2; exit 2; }
git -C "$here" rev-parse --git-dir >/dev/null 2>&1 ||
  { echo "mutants: $here is not a git checkout (git ls-files says what to copy)" >&2; exit 2; }
command -v python3 >/dev/null || { echo "mutants: needs python3" >&2; exit 2; }
work=${MUTANTS_DIR:-$here/build-mutants}
mkdir -p "$work" && work=$(cd "$work" && pwd)
jobs=${JOBS:-$(nproc)}
timeout_s=${MUTANTS_TEST_TIMEOUT:-600}

# ---- the list: blocks of "key: value" lines separated by blank lines ----
names=() files=() froms=() tos=() tests=() whys=()
parse() {
  local name="" file="" from="" to="" t="" why="" line key val n=0 in_ci=0
  flush() {
    if [ -n "$name$file$from$to$t" ]; then
      if [ -z "$name" ] || [ -z "$file" ] || [ -z "$from" ] || [ -z "$to" ] || [ -z "$t" ]; then
        echo "mutants: $list: entry ending at line $n needs name, file, from, to and tests" >&2
        exit 2
      fi
      if { [ -z "$only" ] || [[ $only == *",$name,"* ]]; } && { [ $ci -eq 0 ] || [ $in_ci -eq 1 ]; }; then
        names+=("$name") files+=("$file") froms+=("$from") tos+=("$to") tests+=("$t") whys+=("$why")
      fi
    fi
    name="" file="" from="" to="" t="" why=""
  }
  while IFS= read -r line || [ -n "$line" ]; do
    n=$((n + 1))
    case $line in
      '# ----'*'[ci]') in_ci=1; continue ;;
      '# ----'*) in_ci=0; continue ;;
      '#'*) continue ;;
      '') flush; continue ;;
    esac
    key=${line%%:*}
    val=${line#*:}
    val=${val# }
    case $key in
      name) name=$val ;; file) file=$val ;; from) from=$val ;; to) to=$val ;; tests) t=$val ;; why) why=$val ;;
      *) echo "mutants: $list:$n: unknown key '$key'" >&2; exit 2 ;;
    esac
  done <"$list"
  flush
}
parse
if [ -n "$only" ]; then
  for want in ${only//,/ }; do
    found=0
    for nm in "${names[@]}"; do [ "$nm" = "$want" ] && found=1; done
    [ $found -eq 1 ] || { echo "mutants: no entry named $want in $list" >&2; exit 2; }
  done
fi
[ ${#names[@]} -gt 0 ] || { echo "mutants: no entries in $list" >&2; exit 2; }

# substitute FILE FROM TO [OUT]: exact text replacement ("\n" in FROM/TO is a
# newline); the original must occur exactly once. Exit 3: not found (stale),
# 4: more than once (ambiguous). Without OUT only checks.
substitute() {
  python3 - "$@" <<'PY'
import sys
path, a, b = sys.argv[1], sys.argv[2].replace("\\n", "\n"), sys.argv[3].replace("\\n", "\n")
text = open(path, encoding="utf-8").read()
n = text.count(a)
if n == 0: sys.exit(3)
if n > 1: sys.exit(4)
if len(sys.argv) > 4:
    open(sys.argv[4], "w", encoding="utf-8").write(text.replace(a, b))
PY
}

# ---- every entry must still find its text in the working tree ----
stale=0
for i in "${!names[@]}"; do
  f=$here/${files[$i]}
  if [ ! -f "$f" ]; then
    echo "mutants: stale mutation ${names[$i]}: ${files[$i]} does not exist" >&2
    stale=$((stale + 1))
    continue
  fi
  substitute "$f" "${froms[$i]}" "${tos[$i]}"
  case $? in
    0) ;;
    3) echo "mutants: stale mutation ${names[$i]}: ${files[$i]} no longer contains: ${froms[$i]}" >&2
       stale=$((stale + 1)) ;;
    4) echo "mutants: ambiguous mutation ${names[$i]}: ${files[$i]} contains more than once: ${froms[$i]}" >&2
       stale=$((stale + 1)) ;;
    *) echo "mutants: ${names[$i]}: cannot read ${files[$i]}" >&2; stale=$((stale + 1)) ;;
  esac
done
if [ $stale -gt 0 ]; then
  echo "mutants: $stale stale or ambiguous entr$([ $stale -eq 1 ] && echo y || echo ies) in $list: re-target them to the current code" >&2
  exit 1
fi
if [ $check_only -eq 1 ]; then
  echo "mutants: all ${#names[@]} entries find their original text"
  exit 0
fi

# ---- the scratch copy: tracked and untracked-but-not-ignored files; a file
# is copied (with a new mtime, so that make rebuilds it) only when its content
# differs, so unchanged objects stay valid between runs ----
src=$work/src
bld=$work/build
mkdir -p "$src" "$bld"
copied=0
while IFS= read -r -d '' f; do
  [ -f "$here/$f" ] || continue
  if ! cmp -s "$here/$f" "$src/$f"; then
    mkdir -p "$src/$(dirname "$f")"
    cp "$here/$f" "$src/$f"
    copied=$((copied + 1))
  fi
done < <(cd "$here" && git ls-files -z --cached --others --exclude-standard)
shared=$(cd "$here/.." && pwd)/shared
t0=$(date +%s)
echo "mutants: ${#names[@]} mutations of $list; scratch copy in $src ($copied files refreshed)"
cmake -S "$src" -B "$bld" -DCMAKE_BUILD_TYPE=Release -DJND_WERROR=OFF -DJND_SHARED_DIR="$shared" >/dev/null ||
  { echo "mutants: cmake failed in $bld" >&2; exit 2; }
# build [TARGET...]: incremental build of the targets (all when none)
build() {
  local t=() x
  for x in "$@"; do t+=(--target "$x"); done
  cmake --build "$bld" -j "$jobs" ${t[@]+"${t[@]}"} >"$work/build.log" 2>&1
}
build || { tail -30 "$work/build.log" >&2; echo "mutants: the unmutated copy does not build" >&2; exit 2; }

# the build targets the tests need: unit.test_x is test_x; e2e tests run jnd
targets_of() {
  local t
  for t in $1; do
    case $t in unit.*) echo "${t#unit.}" ;; *) echo jnd ;; esac
  done | sort -u | paste -sd' '
}
regex_of() { echo "^($(echo "$1" | tr -s ' ' '\n' | sed '/^$/d' | sed 's/\./\\./g' | paste -sd'|'))\$"; }
# run_tests "NAME..." [EXTRA CTEST ARGS]: runs them (in parallel) and prints
# the names of those that failed
run_tests() {
  local regex
  regex=$(regex_of "$1"); shift
  (cd "$bld" && OMP_WAIT_POLICY=passive ctest -j "$jobs" --timeout "$timeout_s" --no-tests=error -R "$regex" "$@" \
     >"$work/ctest.log" 2>&1)
  awk '/^The following tests FAILED:/ { on = 1; next } on && /^[[:space:]]+[0-9]+ - / { print $3; next } { on = 0 }' \
    "$work/ctest.log" | sort -u | paste -sd' '
}
# first_failing "NAME...": runs them one at a time, in order; prints the first that fails
first_failing() {
  local t
  for t in $1; do
    (cd "$bld" && OMP_WAIT_POLICY=passive ctest --timeout "$timeout_s" --no-tests=error -R "$(regex_of "$t")" \
       >"$work/ctest.log" 2>&1) || { echo "$t"; return; }
  done
}
fast_suite=$(cd "$bld" && ctest -N -LE slow | sed -n 's/^[[:space:]]*Test *#[0-9]*: \(.*\)$/\1/p' | paste -sd' ')

# ---- baseline: the tests the list names must pass without any mutation ----
if [ $all -eq 1 ]; then
  union=$fast_suite
else
  union=$(printf '%s\n' "${tests[@]}" | tr -s ' ' '\n' | sed '/^$/d' | sort -u | paste -sd' ')
fi
base_fail=$(run_tests "$union")
ran=$(sed -n 's/.*tests failed out of \([0-9]*\).*/\1/p' "$work/ctest.log")
if [ -n "$base_fail" ] || [ "${ran:-0}" -eq 0 ]; then
  cat "$work/ctest.log" >&2
  echo "mutants: without any mutation these tests fail: ${base_fail:-(none ran)}; fix the suite first" >&2
  exit 2
fi
echo "mutants: baseline: the $ran tests pass on the unmutated copy ($(($(date +%s) - t0)) s)"

# ---- one mutation at a time ----
survived=0 broken=0
for i in "${!names[@]}"; do
  ti=$(date +%s)
  f=${files[$i]}
  cp -p "$src/$f" "$work/original"
  if ! substitute "$src/$f" "${froms[$i]}" "${tos[$i]}" "$work/mutant"; then
    echo "mutants: ${names[$i]}: the scratch copy of $f differs from the working tree" >&2
    exit 2
  fi
  cp "$work/mutant" "$src/$f"
  caught="" built=1
  if [ $all -eq 1 ]; then
    if build; then caught=$(run_tests "$fast_suite"); else built=0; fi
  elif build $(targets_of "${tests[$i]}"); then
    caught=$(first_failing "${tests[$i]}")
    if [ -z "$caught" ]; then
      # its tests missed it: does anything else in the fast suite catch it?
      others=$(echo "$fast_suite" | tr ' ' '\n' | grep -vxF -f <(echo "${tests[$i]}" | tr -s ' ' '\n' | sed '/^$/d') | paste -sd' ')
      if ! build; then
        built=0
      elif [ -n "$others" ]; then
        caught=$(run_tests "$others")
        [ -n "$caught" ] && caught="$caught (not by its listed tests)"
      fi
    fi
  else
    built=0
  fi
  if [ $built -eq 0 ]; then
    verdict="BUILD FAILED"
    broken=$((broken + 1))
    grep -m3 'error' "$work/build.log" | sed 's/^/      /' >&2
  elif [ -n "$caught" ]; then
    verdict="caught by $caught"
  else
    verdict="SURVIVED"
    survived=$((survived + 1))
  fi
  # restore: the original content with a new mtime, so that the next build recompiles it
  cp "$work/original" "$src/$f"
  touch "$src/$f"
  printf '%-28s %-28s %4ss  %s\n' "${names[$i]}" "$f" "$(($(date +%s) - ti))" "$verdict"
done
build || true # leave the scratch build unmutated

echo
echo "mutants: ${#names[@]} mutations, $((${#names[@]} - survived - broken)) caught, $survived survived, $broken did not build; $(($(date +%s) - t0)) s"
[ $survived -eq 0 ] && [ $broken -eq 0 ]
