# ctest core.include_boundary: the map core (include/hazmap/{core,map,rules,hazard} and
# src/{core,map,rules,hazard}) includes none of the other modules' headers (io, stereo,
# camera, pipeline, eval, sim, app) and none of OpenCV, spdlog, fmt, yaml-cpp, GDAL or
# zlib. Prints file:line of every offending #include and fails. hazmap_core's compile
# enforces the libraries too (cmake/core_boundary.cmake); this also catches the modules,
# whose headers are on the core's include path.
#   cmake -DHAZMAP_SOURCE_DIR=<repo> -P cmake/check_core_includes.cmake
if(NOT HAZMAP_SOURCE_DIR)
  get_filename_component(HAZMAP_SOURCE_DIR "${CMAKE_CURRENT_LIST_DIR}/.." ABSOLUTE)
endif()

set(modules core map rules hazard)
set(files)
foreach(m IN LISTS modules)
  file(GLOB_RECURSE found
       ${HAZMAP_SOURCE_DIR}/include/hazmap/${m}/*.hpp ${HAZMAP_SOURCE_DIR}/include/hazmap/${m}/*.h
       ${HAZMAP_SOURCE_DIR}/src/${m}/*.cpp ${HAZMAP_SOURCE_DIR}/src/${m}/*.hpp
       ${HAZMAP_SOURCE_DIR}/src/${m}/*.h)
  list(APPEND files ${found})
endforeach()
list(SORT files)

set(forbidden_modules "(^|/)(io|stereo|camera|pipeline|eval|sim|app)/")
set(forbidden_libraries "^(opencv2?|spdlog|fmt|yaml-cpp|gdal|pybind11)/|^(yaml|zlib|zconf|gdal[a-z_]*|cpl_[a-z_]*|ogr_[a-z_]*)\\.h$")

include(${CMAKE_CURRENT_LIST_DIR}/read_source_lines.cmake)
set(bad 0)
foreach(f IN LISTS files)
  hazmap_read_source_lines("${f}" lines)
  set(n 0)
  file(RELATIVE_PATH rel "${HAZMAP_SOURCE_DIR}" "${f}")
  foreach(line IN LISTS lines)
    math(EXPR n "${n} + 1")
    if(line MATCHES "^[ \t]*#[ \t]*include[ \t]*[<\"]([^>\"]+)[>\"]")
      set(inc "${CMAKE_MATCH_1}")
      if(inc MATCHES "${forbidden_modules}")
        message("${rel}:${n}: #include of ${inc}: the map core may not include the ${CMAKE_MATCH_2} module")
        math(EXPR bad "${bad} + 1")
      elseif(inc MATCHES "${forbidden_libraries}")
        message("${rel}:${n}: #include of ${inc}: the map core depends on Eigen only")
        math(EXPR bad "${bad} + 1")
      endif()
    endif()
  endforeach()
endforeach()

list(LENGTH files count)
if(bad GREATER 0)
  message(FATAL_ERROR "map core include boundary: ${bad} offending #include(s) in ${count} files")
endif()
message("map core include boundary: ${count} files, no include of another module or of OpenCV, spdlog, fmt, yaml-cpp, GDAL or zlib")
