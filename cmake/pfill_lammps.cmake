# The LAMMPS engine (`pfill fill --engine lammps`, docs/lammps_engine.md):
# PFILL_WITH_LAMMPS = AUTO (default: built when find_package finds LAMMPS
# and MPI), ON (required), OFF (left out). Sets PFILL_HAVE_LAMMPS ON/OFF.
# Without it the layer pfill_lammps holds only src/lammps/lammps_unavailable.cpp,
# whose entry points say "this pfill was built without LAMMPS".
set(PFILL_WITH_LAMMPS AUTO CACHE STRING "The LAMMPS engine: AUTO (when LAMMPS and MPI are found), ON, OFF")
set_property(CACHE PFILL_WITH_LAMMPS PROPERTY STRINGS AUTO ON OFF)
set(PFILL_HAVE_LAMMPS OFF)
if(NOT PFILL_WITH_LAMMPS STREQUAL "OFF")
  if(PFILL_WITH_LAMMPS STREQUAL "ON")
    find_package(MPI REQUIRED COMPONENTS CXX)
    find_package(LAMMPS REQUIRED)
  else()
    find_package(MPI QUIET COMPONENTS CXX)
    # Debian's LAMMPS package config names /usr/bin/lmp (package lammps) and
    # stops configuring when it is absent, QUIET or not: look before asking.
    find_file(PFILL_LAMMPS_CONFIG LAMMPSConfig.cmake
      PATH_SUFFIXES lib/${CMAKE_LIBRARY_ARCHITECTURE}/cmake/LAMMPS lib/cmake/LAMMPS)
    find_program(PFILL_LMP lmp)
    if(MPI_CXX_FOUND AND PFILL_LAMMPS_CONFIG AND NOT PFILL_LMP)
      message(STATUS "pfill: LAMMPS found without its lmp program (Debian package lammps): the LAMMPS engine is left out")
    elseif(MPI_CXX_FOUND)
      find_package(LAMMPS QUIET)
    endif()
  endif()
  if(MPI_CXX_FOUND AND TARGET LAMMPS::lammps)
    set(PFILL_HAVE_LAMMPS ON)
    find_program(PFILL_MPIEXEC NAMES mpirun mpiexec)
  endif()
endif()
message(STATUS "pfill: the LAMMPS engine: ${PFILL_HAVE_LAMMPS} (PFILL_WITH_LAMMPS=${PFILL_WITH_LAMMPS})")

# pfill_lammps_layer(): after the layers below it exist.
function(pfill_lammps_layer)
  pfill_layer(lammps USES engine boundary)  # boundary: the wall computed from the mesh (exact_field.hpp)
  if(PFILL_HAVE_LAMMPS)
    target_link_libraries(pfill_lammps PRIVATE LAMMPS::lammps MPI::MPI_CXX)
    target_compile_definitions(pfill_lammps PRIVATE PFILL_WITH_LAMMPS=1 OMPI_SKIP_MPICXX=1 MPICH_SKIP_MPICXX=1)
  endif()
endfunction()
