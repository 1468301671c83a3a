# Registers one ctest test per GoogleTest test suite of a test executable (tests/CMakeLists.txt,
# lgvi_add_gtest_suites): run after each build of the executable, it lists the executable's tests
# (--gtest_list_tests) and writes CTEST_FILE with, for each suite S, the test "S" running
# `EXECUTABLE --gtest_filter=S.*`.
#
# Why suites and not single tests: a test process of the sanitized build costs ~0.17 s before its
# first assertion (the runtime's set-up and the executable's static initialization), so 2,835
# one-test processes spent ~480 s of the CI's ~1,370 s of test time starting (CTestCostData of a
# fresh `.ci/run`); the ~210 suites spend ~35 s. `ctest -R` still selects by suite name and a
# failure's output names the failing test; -DLGVI_CTEST_EACH_TEST=ON registers every test alone.
#
# Inputs (-D): EXECUTABLE, CTEST_FILE, TIMEOUT (seconds per suite), TEST_PREFIX (prepended to
# each suite's name), COSTS_FILE (test_costs.txt: a suite listed there gets its COST).
execute_process(COMMAND ${EXECUTABLE} --gtest_list_tests
  OUTPUT_VARIABLE listing RESULT_VARIABLE rc ERROR_VARIABLE errors TIMEOUT 60)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${EXECUTABLE} --gtest_list_tests failed (${rc}):\n${errors}${listing}")
endif()

include(${CMAKE_CURRENT_LIST_DIR}/../cmake/test_cost.cmake)

string(REPLACE ";" "\\;" listing "${listing}")
string(REPLACE "\n" ";" lines "${listing}")
set(content "")
set(count 0)
foreach(line IN LISTS lines)
  # A suite line starts in the first column and its name ends with '.' (a typed or parameterized
  # suite's line goes on with "  # TypeParam = ..."); test lines are indented; gtest_main's own
  # lines ("Running main() ...") and the tests' seed line do not end their first word with '.'.
  if(line MATCHES "^([^ #][^ ]*)\\.( .*)?$")
    set(suite "${CMAKE_MATCH_1}")
    string(APPEND content "add_test([=[${TEST_PREFIX}${suite}]=] [==[${EXECUTABLE}]==] [=[--gtest_filter=${suite}.*]=])\n"
      "set_tests_properties([=[${TEST_PREFIX}${suite}]=] PROPERTIES TIMEOUT ${TIMEOUT})\n")
    if(COSTS_FILE)
      lgvi_test_cost_of("${COSTS_FILE}" "${TEST_PREFIX}${suite}" cost)
      if(cost)
        string(APPEND content "set_tests_properties([=[${TEST_PREFIX}${suite}]=] PROPERTIES COST ${cost})\n")
      endif()
    endif()
    math(EXPR count "${count} + 1")
  endif()
endforeach()
if(count EQUAL 0)
  message(FATAL_ERROR "${EXECUTABLE}: no test suite in its --gtest_list_tests output")
endif()
file(WRITE "${CTEST_FILE}" "${content}")
