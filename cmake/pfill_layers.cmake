# The library's layers (ARCHITECTURE.md, ../shared/DESIGN.md "which part
# may use which"), one OBJECT library each: pfill_<layer> built from
# src/<layer>/*.cpp. A layer sees
#   - its own private headers only: "<layer>/x.hpp" (src/<layer>/, through
#     a folder in the build tree that holds nothing else);
#   - its own public headers and those of the layers it USES (a folder of
#     links per layer into include/pfill/, passed on by target_link_libraries),
# so an #include across the arrows fails to compile. The installed library
# pfill (pfill::pfill) is every layer's objects in one archive.

set(PFILL_LAYER_DIR ${PROJECT_BINARY_DIR}/layers)
set(PFILL_LAYERED_HEADERS "")

# pfill_layer_headers(LAYER header...): LAYER's public headers (paths below include/pfill/).
function(pfill_layer_headers layer)
  set(dir ${PFILL_LAYER_DIR}/public/${layer})
  file(REMOVE_RECURSE ${dir})
  file(MAKE_DIRECTORY ${dir}/pfill)
  foreach(h ${ARGN})
    if(NOT EXISTS ${PROJECT_SOURCE_DIR}/include/pfill/${h})
      message(FATAL_ERROR "pfill layers: include/pfill/${h} (layer ${layer}) does not exist")
    endif()
    get_filename_component(sub ${dir}/pfill/${h} DIRECTORY)
    file(MAKE_DIRECTORY ${sub})
    file(CREATE_LINK ${PROJECT_SOURCE_DIR}/include/pfill/${h} ${dir}/pfill/${h} SYMBOLIC)
  endforeach()
  set(all ${PFILL_LAYERED_HEADERS} ${ARGN})
  set(PFILL_LAYERED_HEADERS ${all} PARENT_SCOPE)
endfunction()

# pfill_layer(LAYER [USES layer...] [LIBS target...] [SOURCES file...])
function(pfill_layer layer)
  cmake_parse_arguments(L "" "" "USES;LIBS;SOURCES" ${ARGN})
  set(target pfill_${layer})
  if(EXISTS ${PROJECT_SOURCE_DIR}/src/${layer})
    file(GLOB sources CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/src/${layer}/*.cpp)
    set(private ${PFILL_LAYER_DIR}/private/${layer})
    file(MAKE_DIRECTORY ${private})
    if(NOT EXISTS ${private}/${layer})
      file(CREATE_LINK ${PROJECT_SOURCE_DIR}/src/${layer} ${private}/${layer} SYMBOLIC)
    endif()
  endif()
  if(NOT sources AND NOT L_SOURCES)
    add_library(${target} INTERFACE)
    target_include_directories(${target} INTERFACE ${PFILL_LAYER_DIR}/public/${layer})
    foreach(u ${L_USES})
      target_link_libraries(${target} INTERFACE pfill_${u})
    endforeach()
    return()
  endif()
  add_library(${target} OBJECT ${sources} ${L_SOURCES})
  target_include_directories(${target} PUBLIC ${PFILL_LAYER_DIR}/public/${layer})
  if(private)
    target_include_directories(${target} PRIVATE ${private})
  endif()
  foreach(u ${L_USES})
    target_link_libraries(${target} PUBLIC pfill_${u})
  endforeach()
  target_link_libraries(${target} PRIVATE ${L_LIBS})
  target_compile_features(${target} PUBLIC cxx_std_17)
  target_compile_definitions(${target} PUBLIC CL_TARGET_OPENCL_VERSION=120 CL_HPP_TARGET_OPENCL_VERSION=120
                                              CL_HPP_MINIMUM_OPENCL_VERSION=120)
  # -ffp-contract=off: host formulas (physics_double.hpp) in the order
  # written, never a*b+c fused where the ISA has FMA (aarch64; the LAMMPS
  # engine's FMA clones, src/lammps/fma_clones.hpp), so every build
  # computes the same bits.
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -ffp-contract=off)
  # Position-independent, so the Python module (a shared object) can link the archive.
  set_target_properties(${target} PROPERTIES POSITION_INDEPENDENT_CODE ON)
endfunction()

# Every public header belongs to one layer.
function(pfill_check_layered_headers)
  file(GLOB_RECURSE headers RELATIVE ${PROJECT_SOURCE_DIR}/include/pfill CONFIGURE_DEPENDS
       ${PROJECT_SOURCE_DIR}/include/pfill/*.hpp)
  foreach(h ${headers})
    if(NOT h IN_LIST PFILL_LAYERED_HEADERS)
      message(FATAL_ERROR "pfill layers: include/pfill/${h} belongs to no layer; add it to a "
                          "pfill_layer_headers() line in CMakeLists.txt")
    endif()
  endforeach()
endfunction()
