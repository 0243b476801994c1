#!/usr/bin/env bash
# libjnd.so exports exactly the functions include/jnd.h declares: nothing
# internal leaks (issue 9 found 76 symbols that were not in the header, some
# without the jnd_ prefix), and every declared function exists.
. "$(dirname "$0")/lib.bash"
: "${JND_LIB:?JND_LIB must point at libjnd.so}"
command -v nm >/dev/null || skip "needs nm (binutils)"
command -v python3 >/dev/null || skip "needs python3"
nm -D --defined-only "$JND_LIB" | awk '$2 ~ /^[TtWwDdBbRr]$/ {print $3}' | sed 's/@.*//' | sort -u >"$T/exported.txt"
python3 - "$JND_SRC/include/jnd.h" >"$T/declared.txt" <<'PY'
import re, sys
text = open(sys.argv[1]).read()
text = re.sub(r"/\*.*?\*/", "", text, flags=re.S)
text = re.sub(r"//[^\n]*", "", text)
print("\n".join(sorted(set(re.findall(r"\b(jnd_[A-Za-z0-9_]+)\s*\(", text)))))
PY
check "the header declares the API (sanity: over 150 functions)" [ "$(wc -l <"$T/declared.txt")" -gt 150 ]
comm -23 "$T/exported.txt" "$T/declared.txt" >"$T/extra.txt"
check "libjnd.so exports nothing the header does not declare ($(head -c 300 "$T/extra.txt" | tr '\n' ' '))" [ ! -s "$T/extra.txt" ]
comm -13 "$T/exported.txt" "$T/declared.txt" >"$T/missing.txt"
check "every function the header declares is exported ($(head -c 300 "$T/missing.txt" | tr '\n' ' '))" [ ! -s "$T/missing.txt" ]
# issue 24's task shape: under src/tasks only the viewer/judge (judge.c) makes a renderer or shows frames as
# the display shows them, besides render_run.c (whose product is the rendering) and the tasks whose inputs
# are images a user gives (diff, pop from files); a task asks judge_renderer for its renderer
grep -l 'jnd_renderer_create *(' "$JND_SRC"/src/tasks/*.c | xargs -r -n1 basename | grep -vxE 'judge\.c|render_run\.c' >"$T/makers.txt"
check "task shape: no task makes its own renderer ($(tr '\n' ' ' <"$T/makers.txt"))" [ ! -s "$T/makers.txt" ]
grep -lE 'jnd_(render_to_srgb|display_apply) *\(' "$JND_SRC"/src/tasks/*.c | xargs -r -n1 basename |
  grep -vxE 'judge\.c|render_run\.c|diff\.c|diff_run\.c|pop\.c' >"$T/shows.txt"
check "task shape: no task converts frames to the display its own way ($(tr '\n' ' ' <"$T/shows.txt"))" [ ! -s "$T/shows.txt" ]
# every report is built by the library (src/tasks/*_report.c): the CLI holds no cJSON at all
grep -l 'cJSON' "$JND_SRC"/src/cli/*.c "$JND_SRC"/src/cli/*.h 2>/dev/null | xargs -r -n1 basename >"$T/cli_json.txt"
check "task shape: src/cli builds no JSON ($(tr '\n' ' ' <"$T/cli_json.txt"))" [ ! -s "$T/cli_json.txt" ]
# the header's two tiers (issue 24 item 5): a declaration marked JND_EXPERIMENTAL is the experimental tier,
# every other one the core; the library exports exactly the two together (checked above), each name in one tier
python3 - "$JND_SRC/include/jnd.h" "$T" <<'PY'
import re, sys
text = re.sub(r"/\*.*?\*/", "", open(sys.argv[1]).read(), flags=re.S)
declared = set(re.findall(r"\b(jnd_[A-Za-z0-9_]+)\s*\(", text))
marked = re.findall(r"^JND_EXPERIMENTAL [^(;]*?\b(jnd_[A-Za-z0-9_]+)\(", text, flags=re.M)
unmarked = re.findall(r"^(?!JND_EXPERIMENTAL|typedef|#)[A-Za-z][^(;=]*?\b(jnd_[A-Za-z0-9_]+)\(", text, flags=re.M)
open(sys.argv[2] + "/experimental.txt", "w").write("\n".join(sorted(set(marked))) + "\n")
open(sys.argv[2] + "/core.txt", "w").write("\n".join(sorted(declared - set(marked))) + "\n")
open(sys.argv[2] + "/both.txt", "w").write("\n".join(sorted(set(marked) & set(unmarked))))
PY
check "tiers: no function is declared in both ($(head -c 300 "$T/both.txt" | tr '\n' ' '))" [ ! -s "$T/both.txt" ]
check "tiers: the experimental tier is marked (sanity: over 100 functions)" [ "$(wc -l <"$T/experimental.txt")" -gt 100 ]
for task in texres pca calibrate lod render diff csf gaze pop; do
  check "tiers: jnd_${task}_run, its defaults and its result's free are core" bash -c \
    "grep -qx 'jnd_${task}_run' '$T/core.txt' && grep -Eqx 'jnd_${task}(_run)?_defaults' '$T/core.txt' && grep -Eqx 'jnd_${task}(_run)?_result_free' '$T/core.txt'"
done
check "tiers: no figure, plot or test counter in the core ($(grep -E '_(figure|plot|counts)$' "$T/core.txt" | tr '\n' ' '))" \
  bash -c "! grep -Eq '_(figure|plot|counts)\$' '$T/core.txt'"
# the header's examples as programs (compiled here against the tiers, below against the install): the
# first, the product (texres), and the image diff
example() {   # the heading's first words
  python3 - "$JND_SRC/include/jnd.h" "$1" <<'PY'
import re, sys
text = open(sys.argv[1]).read()
body = text.split(sys.argv[2], 1)[1].split("\n *\n", 1)[1].split("\n *\n", 1)[0]
lines = [re.sub(r"^ \*     ", "", l) for l in body.splitlines()]
print('#include <stdio.h>\n#include <jnd.h>\nint main(void) {\n' + "\n".join(lines) + '\n  return 0;\n}')
PY
}
example "Ten lines to make a model's textures" >"$T/product.c"
example "Ten lines to compare two images" >"$T/first.c"
check "the header opens with the product: a texres run, its status checked, its result freed" \
  bash -c "head -c 1500 '$JND_SRC/include/jnd.h' | grep -q 'Ten lines to make a model' && grep -q 'jnd_texres_run(.*!= JND_OK' '$T/product.c' && grep -q 'jnd_texres_result_free(r)' '$T/product.c'"
# the first example uses the core only: with the mark as a deprecation, it compiles without a warning
if command -v cc >/dev/null; then
  check "tiers: the header's first example uses the core only (experimental marked deprecated, -Werror)" \
    cc -std=c11 -Wall -Werror "-DJND_EXPERIMENTAL=__attribute__((deprecated))" -I"$JND_SRC/include" \
    -fsyntax-only "$T/first.c"
  check "tiers: the header's product example uses the core only (experimental marked deprecated, -Werror)" \
    cc -std=c11 -Wall -Werror "-DJND_EXPERIMENTAL=__attribute__((deprecated))" -I"$JND_SRC/include" \
    -fsyntax-only "$T/product.c"
  printf '#include <jnd.h>\nint main(void) { return jnd_seconds() > 0 ? 0 : 1; }\n' >"$T/experimental_use.c"
  check "tiers: and the mark does warn where a program leaves the core (jnd_seconds)" bash -c \
    "! cc -std=c11 -Werror '-DJND_EXPERIMENTAL=__attribute__((deprecated))' -I'$JND_SRC/include' -fsyntax-only '$T/experimental_use.c' 2>/dev/null"
fi
# installed (cmake --install, as `make install PREFIX=` does) and linked the way the README says (pkg-config),
# the header's first example compiles, runs without LD_LIBRARY_PATH, and checks its reads: a missing file is
# one line and exit 2, never "P(detect) = 0.000"
if command -v cc >/dev/null && command -v pkg-config >/dev/null; then
  cmake --install "$(dirname "$JND_LIB")" --prefix "$T/prefix" >"$T/install.log" 2>&1
  check "installs into a prefix" [ -f "$T/prefix/include/jnd.h" ]
  pc=$(find "$T/prefix" -name jnd.pc | head -1)
  flags=$(PKG_CONFIG_PATH=$(dirname "$pc") pkg-config --cflags --libs jnd)
  # the sanitizer build's library needs its runtime in the program that links it
  cc=(cc)
  if [ -n "${JND_SANITIZED:-}" ]; then cc=(clang -fsanitize=address,undefined); fi
  check "the header's first example compiles against the installed library ($flags)" \
    "${cc[@]}" -std=c11 -Wall -Werror -o "$T/first" "$T/first.c" $flags
  check "pkg-config's flags give the program an rpath" bash -c "readelf -d '$T/first' | grep -Eq 'RPATH|RUNPATH'"
  mkdir -p "$T/run"
  (cd "$T/run" && env -u LD_LIBRARY_PATH "$T/first" >"$T/out.txt" 2>"$T/err.txt"; echo $? >"$T/rc.txt")
  check "a missing file: exit 2, one line naming it, no P(detect)" \
    bash -c "[ \$(cat '$T/rc.txt') -eq 2 ] && [ \$(wc -l <'$T/err.txt') -eq 1 ] && grep -q '^jnd: ref.png' '$T/err.txt' && ! grep -q 'P(detect)' '$T/out.txt'"
  check "the header's product example compiles against the installed library" \
    "${cc[@]}" -std=c11 -Wall -Werror -o "$T/product" "$T/product.c" $flags
  (cd "$T/run" && env -u LD_LIBRARY_PATH "$T/product" >"$T/out.txt" 2>"$T/err.txt"; echo $? >"$T/rc.txt")
  check "the product example on a missing model: exit 2, one line naming it, nothing written" \
    bash -c "[ \$(cat '$T/rc.txt') -eq 2 ] && [ \$(wc -l <'$T/err.txt') -eq 1 ] && grep -q '^jnd: model.glb' '$T/err.txt' && [ ! -e '$T/run/smaller' ] && [ ! -s '$T/out.txt' ]"
  "$JND" example -o "$T/run/ex" --size 96x64 >/dev/null 2>&1
  cp "$T/run/ex/reference.png" "$T/run/ref.png" && cp "$T/run/ex/test.png" "$T/run/test.png"
  (cd "$T/run" && env -u LD_LIBRARY_PATH "$T/first" >"$T/out.txt" 2>"$T/err.txt"; echo $? >"$T/rc.txt")
  check "the example pair: exit 0 and a probability" \
    bash -c "[ \$(cat '$T/rc.txt') -eq 0 ] && grep -Eq '^P\(detect\) = [01]\.[0-9]{3}, max JND' '$T/out.txt'"
else
  skip "needs cc and pkg-config to build the header's example"
fi
finish
