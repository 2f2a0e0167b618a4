# CTest splits a discovered Catch test whose name holds a semicolon into entries that match no
# test and "pass" without running anything. Fails when any test name has one.
execute_process(COMMAND "${TEST_BINARY}" --list-test-names-only OUTPUT_VARIABLE names
                RESULT_VARIABLE rc)
if(NOT rc EQUAL 0 AND NOT rc EQUAL 1)
  message(FATAL_ERROR "could not list the tests of ${TEST_BINARY} (exit ${rc})")
endif()
string(FIND "${names}" ";" at)
if(NOT at EQUAL -1)
  string(REPLACE "\n" " | " flat "${names}")
  message(FATAL_ERROR "a test name holds ';' (CTest would split it and run nothing): ${flat}")
endif()
message(STATUS "every test name is safe for CTest")
