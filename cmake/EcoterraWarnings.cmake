# Warnings every ecoterra target is built with; the build must stay clean of them.
add_library(ecoterra_warnings INTERFACE)
target_compile_options(ecoterra_warnings INTERFACE -Wall -Wextra -Wpedantic -Wshadow
                                                   -Wnon-virtual-dtor -Woverloaded-virtual)
# CI builds with ECOTERRA_WERROR=ON (.ci/run): a warning fails the build there.
option(ECOTERRA_WERROR "Treat compiler warnings as errors (CI builds)" OFF)
if(ECOTERRA_WERROR)
  target_compile_options(ecoterra_warnings INTERFACE -Werror)
endif()
add_library(ecoterra_options INTERFACE)
if(ECOTERRA_NATIVE)
  target_compile_options(ecoterra_options INTERFACE -march=native)
endif()
# Eigen's own threading is switched off: ecoterra parallelises over fixed blocks with OpenMP so
# that results do not depend on the thread count.
target_compile_definitions(ecoterra_options INTERFACE EIGEN_DONT_PARALLELIZE)
# The glue around the libraries (the program's command layer, the Python bindings, the tests' own
# sources) holds no hot loop: the work is in the libraries, which keep their build's flags. It
# compiles at -O1 in an optimised build (a command file took 15.2 s at -O3 and 10.4 s at -O1) and,
# under the fuzzing build (scripts/sanitize.sh), at -O0 without coverage counters (only the fuzzed
# libraries need them; the sanitizers stay): minutes off CI's two builds. Debug builds keep -O0.
# The option comes after the build type's flags and wins.
function(ecoterra_glue_options target)
  if(ECOTERRA_FUZZ)
    target_compile_options(${target} PRIVATE -O0 -fno-sanitize=fuzzer-no-link)
  elseif(NOT CMAKE_BUILD_TYPE STREQUAL "Debug")
    target_compile_options(${target} PRIVATE -O1)
  endif()
endfunction()
