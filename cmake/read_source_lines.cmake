# hazmap_read_source_lines(FILE OUT): FILE's lines as a CMake list, one element per line.
# ';' would split a line and '[' ']' can stop a split, so they come back as <sc>, <lb>,
# <rb>. Shared by the include checks (check_core_includes.cmake, check_include_floors.cmake).
function(hazmap_read_source_lines file out)
  file(READ "${file}" text)
  string(REPLACE ";" "<sc>" text "${text}")
  string(REPLACE "[" "<lb>" text "${text}")
  string(REPLACE "]" "<rb>" text "${text}")
  string(REPLACE "\n" ";" lines "${text}")
  set(${out} "${lines}" PARENT_SCOPE)
endfunction()
