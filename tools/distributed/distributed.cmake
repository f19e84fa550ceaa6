# Distributed rendering for `principled render` (tools/distributed/, docs/distributed.md):
# MPI sample/frame splitting when MPI is found, checkpoints and --frames always.
option(PRINCIPLED_WITH_MPI "Distributed rendering under mpirun (on when MPI is found)" ON)
target_sources(principled PRIVATE
  ${CMAKE_CURRENT_LIST_DIR}/accumulation.cpp
  ${CMAKE_CURRENT_LIST_DIR}/comm.cpp
  ${CMAKE_CURRENT_LIST_DIR}/distributedRender.cpp)
target_link_libraries(principled PRIVATE OpenImageIO::lib)
if(PRINCIPLED_WITH_MPI)
  find_package(MPI COMPONENTS CXX QUIET)
  if(MPI_CXX_FOUND)
    target_link_libraries(principled PRIVATE MPI::MPI_CXX)
    target_compile_definitions(principled PRIVATE PRINCIPLED_HAVE_MPI)
    message(STATUS "principled: MPI ${MPI_CXX_VERSION} found: distributed rendering on (mpirun -np N principled render ...)")
  else()
    message(STATUS "principled: MPI not found: distributed rendering off (install libopenmpi-dev)")
  endif()
endif()
# For the tests: whether this build can run under mpirun, and which mpiexec to use.
set(PRINCIPLED_HAVE_MPI_RUNTIME ${MPI_CXX_FOUND} CACHE INTERNAL "")
set(PRINCIPLED_MPIEXEC "${MPIEXEC_EXECUTABLE}" CACHE INTERNAL "")
