# Each case of `parity run`'s matrix as a CTest test, labelled by backend, platform, technique
# and scene (`ctest -L vk`, `ctest -L reference`, `ctest -L forward`). Like gtest_discover_tests,
# the list comes from the built binary when CTest runs (`parity run --list-cases --ctest`), so it
# follows the techniques, scenes and platforms compiled in. Each test runs one case at the CI
# size against the checked-in golden; a case without a checked-in golden is listed disabled.
set(_parity_cases_script "${CMAKE_CURRENT_BINARY_DIR}/parity_cases_include.cmake")
file(GENERATE OUTPUT "${_parity_cases_script}" CONTENT "
execute_process(COMMAND [==[$<TARGET_FILE:parity>]==] run --list-cases --ctest
                        --ctest-out-root [==[${CMAKE_CURRENT_BINARY_DIR}/parity-cases]==]
                OUTPUT_VARIABLE _parity_cases RESULT_VARIABLE _parity_rc ERROR_VARIABLE _parity_err)
if(_parity_rc EQUAL 0)
  cmake_language(EVAL CODE \"\${_parity_cases}\")
else()
  add_test(parity.cases.discovery [==[$<TARGET_FILE:parity>]==] run --list-cases)
endif()
")
set_property(DIRECTORY APPEND PROPERTY TEST_INCLUDE_FILES "${_parity_cases_script}")

# The whole default matrix as one test: the same verdicts as the per-case tests (each case against
# its golden, `parity run`'s rules) plus the GL-Vulkan groups, in one `parity run` whose children
# share one fork server, instead of a `parity` process, fork server and report per case (the
# per-case tests took over a third of the suite's time). scripts/test.sh runs this one and leaves
# out the per-case tests (label `case`); `ctest -L case` runs them.
add_test(NAME parity.matrix COMMAND parity run --out ${CMAKE_CURRENT_BINARY_DIR}/parity-matrix --no-progress)
set_tests_properties(parity.matrix PROPERTIES LABELS "matrix" TIMEOUT 1200)
