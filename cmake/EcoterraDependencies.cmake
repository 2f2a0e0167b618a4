# Every dependency comes from a Debian 12 package; scripts/install-deps.sh installs them.
find_package(Eigen3 3.4 REQUIRED NO_MODULE)            # libeigen3-dev
find_package(OpenMP REQUIRED)                          # gcc's libgomp
find_package(HDF5 REQUIRED COMPONENTS C CXX)           # libhdf5-dev
find_package(nlohmann_json 3.11 REQUIRED)              # nlohmann-json3-dev
find_package(PNG REQUIRED)                             # libpng-dev
find_package(GDAL CONFIG REQUIRED)                     # libgdal-dev
find_package(CLI11 CONFIG REQUIRED)                    # libcli11-dev
find_package(Boost 1.74 REQUIRED)                      # libboost-graph-dev (header-only parts)
find_package(ZLIB REQUIRED)                            # zlib1g-dev (the HDF5 writer's chunks)
find_package(SUNDIALS 6 REQUIRED)                      # libsundials-dev (CVODE, KLU)
find_package(PkgConfig REQUIRED)
pkg_check_modules(FFTW3 REQUIRED IMPORTED_TARGET fftw3) # libfftw3-dev
pkg_check_modules(CAIRO REQUIRED IMPORTED_TARGET cairo)  # libcairo2-dev (run pictures)
if(ECOTERRA_BUILD_TESTS)
  find_package(Catch2 2 REQUIRED)                      # catch2 (v2 in Debian 12)
endif()

# HDF5's CMake support on Debian exposes variables, not targets: wrap them.
if(NOT TARGET ecoterra_hdf5)
  add_library(ecoterra_hdf5 INTERFACE)
  target_include_directories(ecoterra_hdf5 SYSTEM INTERFACE ${HDF5_INCLUDE_DIRS})
  target_link_libraries(ecoterra_hdf5 INTERFACE ${HDF5_CXX_LIBRARIES} ${HDF5_LIBRARIES})
  target_compile_definitions(ecoterra_hdf5 INTERFACE ${HDF5_DEFINITIONS})
endif()
