# Install rules: `cmake --install build --prefix PREFIX` puts the headers, the
# static library, the `pfill` program and the CMake package under PREFIX, so
# another project does
#
#   find_package(pfill CONFIG REQUIRED)
#   target_link_libraries(app PRIVATE pfill::pfill)
#
# with only -DCMAKE_PREFIX_PATH=PREFIX. The kernels are compiled into the
# library (cmake/embed_kernels.cmake), so nothing else is needed at run time.
include(CMakePackageConfigHelpers)

set(PFILL_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/pfill CACHE STRING
    "Where the CMake package files go, relative to the prefix")

install(DIRECTORY ${PROJECT_SOURCE_DIR}/include/pfill DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
        FILES_MATCHING PATTERN "*.hpp")
install(TARGETS pfill EXPORT pfillTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(TARGETS pfill_cli RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(EXPORT pfillTargets NAMESPACE pfill:: FILE pfillTargets.cmake DESTINATION ${PFILL_INSTALL_CMAKEDIR})

configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/pfillConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/pfillConfig.cmake
                              INSTALL_DESTINATION ${PFILL_INSTALL_CMAKEDIR})
# 0.x: minor versions may break the interface, so only the same minor matches.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/pfillConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/pfillConfig.cmake ${PROJECT_BINARY_DIR}/pfillConfigVersion.cmake
        DESTINATION ${PFILL_INSTALL_CMAKEDIR})
