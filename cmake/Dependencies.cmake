# Every dependency comes from a Debian package (scripts/setup.sh installs them).
find_package(Threads REQUIRED)
find_package(Eigen3 3.4 REQUIRED NO_MODULE)
find_package(CLI11 REQUIRED)
find_package(nlohmann_json 3.10 REQUIRED)
if(MATLAS_BUILD_TESTS)
  find_package(GTest REQUIRED)
endif()
if(MATLAS_BUILD_BENCH)
  find_package(benchmark REQUIRED)
endif()
# MPI (Debian: libopenmpi-dev, openmpi-bin), optional: `mpirun -np P matlas build` splits the
# build's pass across ranks (docs/BUILD.md). Without it the command is built as before.
find_package(MPI COMPONENTS CXX QUIET)
include(CMakeDependentOption)
cmake_dependent_option(MATLAS_WITH_MPI "Build the distributed build (mpirun -np P matlas build; needs MPI)" ON
                       "MPI_CXX_FOUND" OFF)
if(MATLAS_WITH_MPI)
  message(STATUS "MPI found (${MPI_CXX_LIBRARY_VERSION_STRING}): `mpirun -np P matlas build` is built")
else()
  message(STATUS "MPI not found or off (Debian: libopenmpi-dev openmpi-bin): matlas build runs in one process")
endif()
