# ctest architecture.include_floors: imports run only down the stages. Every file under
# src/ and include/hazmap/ belongs to the module named by its first folder; an #include of
# "hazmap/<module>/..." (or of a private header "<module>/..." under src/) may name only a
# module on the same floor or a lower one. The floors, bottom to top:
#
#   core < rules = map < hazard < camera < stereo < io < pipeline < eval < sim < app
#
# core, rules, map and hazard form hazmap_core (Eigen only, cmake/check_core_includes.cmake).
# rules and map share a floor: the update rules are templates over the map's point chunks,
# moments and run sums, and the map's layers are templates over the rules, so neither
# compiles without the other. This is also the one kernel exception: header-only rule
# code (include/hazmap/rules/) calls kernels compiled in src/map/ (chunk_runs.cpp,
# run_sums.cpp, kalman_runs.cpp), all inside hazmap_core. app (the CLI) may include
# everything.
# Prints file:line and both modules of every include that goes up a floor, and fails.
#   cmake -DHAZMAP_SOURCE_DIR=<repo> -P cmake/check_include_floors.cmake
cmake_policy(SET CMP0057 NEW)  # if(... IN_LIST ...)
if(NOT HAZMAP_SOURCE_DIR)
  get_filename_component(HAZMAP_SOURCE_DIR "${CMAKE_CURRENT_LIST_DIR}/.." ABSOLUTE)
endif()

set(floor_core 0)
set(floor_rules 1)
set(floor_map 1)
set(floor_hazard 2)
set(floor_camera 3)
set(floor_stereo 4)
set(floor_io 5)
set(floor_pipeline 6)
set(floor_eval 7)
set(floor_sim 8)
set(floor_app 9)
set(modules core rules map hazard camera stereo io pipeline eval sim app)

# Known exceptions, "<file>:<included module>" (file relative to the repository).
set(known_exceptions
)

file(GLOB_RECURSE files
     ${HAZMAP_SOURCE_DIR}/src/*.cpp ${HAZMAP_SOURCE_DIR}/src/*.hpp ${HAZMAP_SOURCE_DIR}/src/*.h
     ${HAZMAP_SOURCE_DIR}/include/hazmap/*.hpp ${HAZMAP_SOURCE_DIR}/include/hazmap/*.h)
list(SORT files)

include(${CMAKE_CURRENT_LIST_DIR}/read_source_lines.cmake)
set(bad 0)
set(checked 0)
foreach(f IN LISTS files)
  file(RELATIVE_PATH rel "${HAZMAP_SOURCE_DIR}" "${f}")
  if(NOT rel MATCHES "^(src|include/hazmap)/([a-z_]+)/")
    message(FATAL_ERROR "${rel}: not inside a module folder (src/<module>/ or include/hazmap/<module>/)")
  endif()
  set(from "${CMAKE_MATCH_2}")
  if(NOT from IN_LIST modules)
    message(FATAL_ERROR "${rel}: module '${from}' has no floor in cmake/check_include_floors.cmake")
  endif()
  math(EXPR checked "${checked} + 1")
  hazmap_read_source_lines("${f}" lines)
  set(n 0)
  foreach(line IN LISTS lines)
    math(EXPR n "${n} + 1")
    if(NOT line MATCHES "^[ \t]*#[ \t]*include[ \t]*\"(hazmap/)?([a-z_]+)/[^\"]+\"")
      continue()
    endif()
    set(to "${CMAKE_MATCH_2}")
    if(NOT to IN_LIST modules)
      continue()  # a folder inside the module, e.g. src/eval's "viewer/viewer_assets.hpp"
    endif()
    if(floor_${to} GREATER floor_${from} AND NOT "${rel}:${to}" IN_LIST known_exceptions)
      message("${rel}:${n}: ${from} includes ${to}, a higher floor: ${line}")
      math(EXPR bad "${bad} + 1")
    endif()
  endforeach()
endforeach()

if(bad GREATER 0)
  message(FATAL_ERROR "include floors: ${bad} include(s) going up the stages in ${checked} files")
endif()
message("include floors: ${checked} files, every include on its own floor or below")
