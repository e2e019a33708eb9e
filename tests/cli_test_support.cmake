# Shared by the command-line test scripts (cli_*_test.cmake, run with
# cmake -P): run(EXPECTED_EXIT_CODE COMMAND...) runs a command and fails the
# test unless it exits with that code; its standard output and error are
# left in `out` and `err`.
function(run expect_rc)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc STREQUAL "${expect_rc}")
    message(FATAL_ERROR "${ARGN}\n exited ${rc}, expected ${expect_rc}:\n${out}\n${err}")
  endif()
  set(out "${out}" PARENT_SCOPE)
  set(err "${err}" PARENT_SCOPE)
endfunction()
