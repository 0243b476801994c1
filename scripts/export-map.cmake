# Writes the linker version script of libjnd.so: the functions include/jnd.h
# declares are global, everything else is local. Run at build time with
# -DHEADER=include/jnd.h -DOUT=jnd.map. tests/e2e/exports.sh checks the
# result with nm.
file(READ ${HEADER} text)
# comments out first: the header's examples mention calls too
string(REGEX REPLACE "/\\*([^*]|\\*+[^*/])*\\*+/" "" text "${text}")
string(REGEX REPLACE "//[^\n]*" "" text "${text}")
string(REGEX MATCHALL "jnd_[A-Za-z0-9_]+[ \t\n]*\\(" calls "${text}")
set(names "")
foreach(c ${calls})
  string(REGEX REPLACE "[ \t\n]*\\($" "" n "${c}")
  list(APPEND names ${n})
endforeach()
list(REMOVE_DUPLICATES names)
list(SORT names)
set(out "/* generated from include/jnd.h by scripts/export-map.cmake */\n{\n  global:\n")
foreach(n ${names})
  string(APPEND out "    ${n};\n")
endforeach()
string(APPEND out "  local:\n    *;\n};\n")
file(WRITE ${OUT}.tmp "${out}")
execute_process(COMMAND ${CMAKE_COMMAND} -E copy_if_different ${OUT}.tmp ${OUT})
