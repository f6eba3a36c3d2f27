# --- cmake --install: the C++ API beside the Python package (wrappers/python/CMakeLists.txt) ---
# Headers under include/openmmdpd, libOpenMMDPD under lib, the platform kernels under
# lib/plugins (OpenMM's own layout: in OpenMM's prefix they load with OpenMM's plugins), and a
# CMake package for find_package(OpenMMDPD).
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(OPENMMDPD_INSTALL_PLUGIN_DIR "${CMAKE_INSTALL_LIBDIR}/plugins")
set(OPENMMDPD_INSTALL_CMAKE_DIR "${CMAKE_INSTALL_LIBDIR}/cmake/OpenMMDPD")

install(DIRECTORY openmmapi/include/openmmdpd DESTINATION "${CMAKE_INSTALL_INCLUDEDIR}"
        FILES_MATCHING PATTERN "*.h" PATTERN "internal" EXCLUDE)
install(TARGETS OpenMMDPD EXPORT OpenMMDPDTargets LIBRARY DESTINATION "${CMAKE_INSTALL_LIBDIR}")
# Installed, a plugin finds libOpenMMDPD one folder up and OpenMM's libraries where it was linked to them.
set_target_properties(${OPENMMDPD_PLUGINS} ${OPENMMDPD_GPU_PLUGINS} PROPERTIES
  INSTALL_RPATH "$ORIGIN/.." INSTALL_RPATH_USE_LINK_PATH TRUE)
set_target_properties(OpenMMDPD PROPERTIES INSTALL_RPATH_USE_LINK_PATH TRUE)
install(TARGETS ${OPENMMDPD_PLUGINS} ${OPENMMDPD_GPU_PLUGINS} LIBRARY DESTINATION "${OPENMMDPD_INSTALL_PLUGIN_DIR}")

install(EXPORT OpenMMDPDTargets NAMESPACE OpenMMDPD:: DESTINATION "${OPENMMDPD_INSTALL_CMAKE_DIR}")
configure_package_config_file(cmake/OpenMMDPDConfig.cmake.in "${CMAKE_BINARY_DIR}/OpenMMDPDConfig.cmake"
  INSTALL_DESTINATION "${OPENMMDPD_INSTALL_CMAKE_DIR}" PATH_VARS OPENMMDPD_INSTALL_PLUGIN_DIR)
write_basic_package_version_file("${CMAKE_BINARY_DIR}/OpenMMDPDConfigVersion.cmake" COMPATIBILITY SameMinorVersion)
install(FILES "${CMAKE_BINARY_DIR}/OpenMMDPDConfig.cmake" "${CMAKE_BINARY_DIR}/OpenMMDPDConfigVersion.cmake"
        DESTINATION "${OPENMMDPD_INSTALL_CMAKE_DIR}")
