# run(WHAT COMMAND...): the install tests' one step: fails the test with the command's output unless it exits 0, and
# leaves its stdout in `output`. Included by install_test.cmake and deb_test.cmake.
function(run what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${what} failed (${rc}):\n${ARGN}\n${out}\n${err}")
  endif()
  set(output "${out}" PARENT_SCOPE)
endfunction()
