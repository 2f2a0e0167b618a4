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
