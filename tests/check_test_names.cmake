# CTest splits a discovered Catch test whose name holds a semicolon into entries that match no
# test and "pass" without running anything. Fails when any test name has one.
# Catch v2 exits with the number of tests listed, so the exit code says nothing here.
execute_process(COMMAND "${TEST_BINARY}" --list-test-names-only OUTPUT_VARIABLE names)
string(LENGTH "${names}" length)
if(length LESS 100)
  message(FATAL_ERROR "could not list the tests of ${TEST_BINARY}")
endif()
string(REGEX MATCHALL "[^\n]*;[^\n]*" semicolon "${names}")
if(semicolon)
  message(FATAL_ERROR "a test name holds ';' (CTest would split it and run nothing): ${semicolon}")
endif()
# A name that starts with '-' reaches Catch as an option (e.g. -o) and runs every test instead.
string(REGEX MATCH "(^|\n)-[^\n]*" dash "${names}")
if(dash)
  message(FATAL_ERROR "a test name starts with '-' (Catch would take it as an option): ${dash}")
endif()
message(STATUS "every test name is safe for CTest")
