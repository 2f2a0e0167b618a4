# Warnings every ecoterra target is built with; the build must stay clean of them.
add_library(ecoterra_warnings INTERFACE)
target_compile_options(ecoterra_warnings INTERFACE -Wall -Wextra -Wpedantic -Wshadow
                                                   -Wnon-virtual-dtor -Woverloaded-virtual)
add_library(ecoterra_options INTERFACE)
if(ECOTERRA_NATIVE)
  target_compile_options(ecoterra_options INTERFACE -march=native)
endif()
# Eigen's own threading is switched off: ecoterra parallelises over fixed blocks with OpenMP so
# that results do not depend on the thread count.
target_compile_definitions(ecoterra_options INTERFACE EIGEN_DONT_PARALLELIZE)
