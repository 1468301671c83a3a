# The COST of one ctest test from tests/test_costs.txt (that file says why): `out` is set to the
# seconds on the line "NAME SECONDS" whose NAME is `test`, or left empty. Used at configure time
# (lgvi_test_cost, CMakeLists.txt) and by tests/gtest_suites.cmake for the suites it registers.
function(lgvi_test_cost_of costs_file test out)
  file(STRINGS "${costs_file}" lines REGEX "^[^#]")
  set(cost "")
  foreach(line IN LISTS lines)
    if(line MATCHES "^([^ ]+) +([0-9.]+)$" AND CMAKE_MATCH_1 STREQUAL test)
      set(cost ${CMAKE_MATCH_2})
    endif()
  endforeach()
  set(${out} "${cost}" PARENT_SCOPE)
endfunction()
