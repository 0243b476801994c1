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
finish
