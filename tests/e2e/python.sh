#!/usr/bin/env bash
# The Python package (python/): its pytest suite against this build's libjnd
# and jnd command. Under the sanitizer build the interpreter is not
# instrumented, so the ASan runtime is preloaded and leak checking is left to
# the C suite (CPython's own allocations at exit are not leaks of ours).
. "$(dirname "$0")/lib.bash"
build=$(dirname "$JND")
py=/usr/bin/python3
if [ ! -f "$build/python/jnd/.built" ]; then
  skip "the Python package was not built (Debian's python3-cffi and python3-numpy: scripts/install-deps.sh)"
fi
if ! "$py" -c "import pytest" 2>/dev/null; then skip "python3-pytest is not installed"; fi
env=(PYTHONPATH="$build/python" JND="$JND" JND_TMP="$T" PYTHONDONTWRITEBYTECODE=1)
if [ -n "${JND_SANITIZED:-}" ]; then
  rt=$(clang -print-file-name=libclang_rt.asan-x86_64.so)
  env+=(LD_PRELOAD="$rt" ASAN_OPTIONS="detect_leaks=0:abort_on_error=1:intercept_tls_get_addr=0")
fi
if env "${env[@]}" "$py" -m pytest -q -p no:cacheprovider --basetemp="$T/pytest" "$JND_SRC/python/tests" >"$T/pytest.txt" 2>&1; then
  ok "pytest: $(tail -1 "$T/pytest.txt")"
else
  cat "$T/pytest.txt"
  bad "pytest"
fi
finish
