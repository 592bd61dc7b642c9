# The insertion driver of tools/bench/compare.sh as a target of a hazmap build:
# included by this tree's CMakeLists.txt (tools), and by compare.sh into the build of
# the revision it compares against (cmake -DCMAKE_PROJECT_hazmap_INCLUDE=<this file>,
# run right after that tree's project(hazmap): the library target is declared later,
# which is fine, CMake links targets by name at generation).
if(NOT TARGET hazmap_insertion_compare)
  add_executable(hazmap_insertion_compare ${CMAKE_CURRENT_LIST_DIR}/insertion_compare.cpp)
  target_link_libraries(hazmap_insertion_compare PRIVATE hazmap)
endif()
