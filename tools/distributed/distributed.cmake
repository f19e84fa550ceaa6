# Distributed rendering for `principled render` (tools/distributed/, docs/distributed.md):
# MPI sample/frame splitting when MPI is found, checkpoints and --frames always.
option(PRINCIPLED_WITH_MPI "Distributed rendering under mpirun (on when MPI is found)" ON)
target_sources(principled PRIVATE
  ${CMAKE_CURRENT_LIST_DIR}/accumulation.cpp
  ${CMAKE_CURRENT_LIST_DIR}/comm.cpp
  ${CMAKE_CURRENT_LIST_DIR}/distributedRender.cpp)
target_link_libraries(principled PRIVATE principled_imageio)
if(PRINCIPLED_WITH_MPI)
  find_package(MPI COMPONENTS CXX QUIET)
  if(MPI_CXX_FOUND)
    # MPI lives in libprincipled_mpi.so (mpiModule.cpp), dlopen()ed only under a launcher:
    # an ordinary render does not load Open MPI's libraries.
    add_library(principled_mpi MODULE ${CMAKE_CURRENT_LIST_DIR}/mpiModule.cpp)
    target_include_directories(principled_mpi PRIVATE ${PROJECT_SOURCE_DIR})
    target_link_libraries(principled_mpi PRIVATE MPI::MPI_CXX principled_warnings)
    set_target_properties(principled_mpi PROPERTIES
      CXX_VISIBILITY_PRESET hidden
      VISIBILITY_INLINES_HIDDEN ON)
    install(TARGETS principled_mpi LIBRARY DESTINATION lib)
    add_dependencies(principled principled_mpi)
    target_link_libraries(principled PRIVATE ${CMAKE_DL_LIBS})
    target_compile_definitions(principled PRIVATE PRINCIPLED_HAVE_MPI
      PRINCIPLED_MPI_BUILD_DIR="$<TARGET_FILE_DIR:principled_mpi>"
      PRINCIPLED_MPI_INSTALL_DIR="${CMAKE_INSTALL_PREFIX}/lib")
    message(STATUS "principled: MPI ${MPI_CXX_VERSION} found: distributed rendering on (mpirun -np N principled render ...)")
  else()
    message(STATUS "principled: MPI not found: distributed rendering off (install libopenmpi-dev)")
  endif()
endif()
# For the tests: whether this build can run under mpirun, and which mpiexec to use.
set(PRINCIPLED_HAVE_MPI_RUNTIME ${MPI_CXX_FOUND} CACHE INTERNAL "")
set(PRINCIPLED_MPIEXEC "${MPIEXEC_EXECUTABLE}" CACHE INTERNAL "")
