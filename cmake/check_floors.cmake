# The floors of the tree, checked on its includes (ctest: layout_floors). Bottom up:
#   lgvi/ -> baselines/ -> experiments/output -> input -> systems -> scene -> methods -> ocp
#   -> suites -> validation/ -> experiments/cli -> experiments/benchmarks
# A file may include a header of its own floor or of a floor below, never one above: the physics
# does not see the harness, a room does not see the rooms built on it. The static libraries'
# link order catches a call that runs back up (CMakeLists.txt, lgvi_harness_room); this check
# catches the include that would start one, header-only code included. tests/, python/ and
# examples/ stand above every floor and are not checked.
# Usage: cmake -DSOURCE_DIR=<checkout> -P cmake/check_floors.cmake   (exit 1 names each arrow up)
if(NOT SOURCE_DIR)
  message(FATAL_ERROR "check_floors.cmake: pass -DSOURCE_DIR=<the source tree>")
endif()

set(floors lgvi baselines experiments/output experiments/input experiments/systems
  experiments/scene experiments/methods experiments/ocp experiments/suites validation
  experiments/cli experiments/benchmarks)

# The floor of a path relative to the source tree (its longest matching prefix), or -1.
function(floor_of path out)
  set(found -1)
  set(index 0)
  foreach(floor ${floors})
    if(path MATCHES "^${floor}/")
      set(found ${index})
    endif()
    math(EXPR index "${index} + 1")
  endforeach()
  set(${out} ${found} PARENT_SCOPE)
endfunction()

set(arrows_up 0)
set(files_checked 0)
foreach(floor ${floors})
  file(GLOB_RECURSE sources RELATIVE ${SOURCE_DIR}
    ${SOURCE_DIR}/${floor}/*.hpp ${SOURCE_DIR}/${floor}/*.cpp ${SOURCE_DIR}/${floor}/*.cpp.in)
  foreach(source ${sources})
    floor_of(${source} own)
    if(NOT own EQUAL -1)
      math(EXPR files_checked "${files_checked} + 1")
      file(STRINGS ${SOURCE_DIR}/${source} includes REGEX "^[ \t]*#[ \t]*include[ \t]*\"")
      foreach(line ${includes})
        string(REGEX REPLACE "^[ \t]*#[ \t]*include[ \t]*\"([^\"]+)\".*" "\\1" header "${line}")
        floor_of(${header} theirs)
        if(theirs GREATER own)
          list(GET floors ${own} own_name)
          list(GET floors ${theirs} their_name)
          message(SEND_ERROR "${source}: includes ${header}: ${their_name} is a floor above ${own_name}")
          math(EXPR arrows_up "${arrows_up} + 1")
        endif()
      endforeach()
    endif()
  endforeach()
endforeach()

if(files_checked EQUAL 0)
  message(FATAL_ERROR "check_floors.cmake: no source found under ${SOURCE_DIR}")
endif()
if(arrows_up GREATER 0)
  message(FATAL_ERROR "check_floors.cmake: ${arrows_up} include(s) run against the floors")
endif()
message(STATUS "check_floors.cmake: ${files_checked} files, no include runs against the floors")
