# ctest python_package_installed: installs the Python component of the build into WORK_DIR and runs
# CHECK with PYTHON from WORK_DIR, PYTHONPATH unset, the installed site folder added the way the
# interpreter adds its own (site.addsitedir): the package must work from there alone.
# Inputs (-D): BUILD_DIR, PYTHON, WORK_DIR, SITE_DIR (relative to the prefix), CHECK.
file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR}/cwd)
execute_process(COMMAND ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${WORK_DIR}/prefix --component python
  RESULT_VARIABLE rc OUTPUT_VARIABLE log ERROR_VARIABLE log)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "cmake --install --component python failed:\n${log}")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} -E env --unset=PYTHONPATH
    ${PYTHON} ${CHECK} ${WORK_DIR}/prefix/${SITE_DIR}
  WORKING_DIRECTORY ${WORK_DIR}/cwd RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the installed package failed its check (${rc})")
endif()
file(REMOVE_RECURSE ${WORK_DIR})
