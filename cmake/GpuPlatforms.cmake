# --- the GPU platforms: kernels written once on OpenMM's ComputeContext (platforms/common), with
# thin factories for OpenCL and CUDA, each built where the OpenMM install has that platform ---
if(NOT OPENMMDPD_BUILD_GPU)
  return()
endif()
find_library(OPENMM_OPENCL_LIBRARY OpenMMOpenCL HINTS "${OPENMM_PLUGIN_DIR}" NO_DEFAULT_PATH)
find_library(OPENMM_CUDA_LIBRARY OpenMMCUDA HINTS "${OPENMM_PLUGIN_DIR}" NO_DEFAULT_PATH)
# Only OpenMM's platform libraries and their Platform headers are needed to build: the kernels
# are compiled at run time by the platform (the OpenCL ICD or the CUDA driver, where they exist).
set(OPENMMDPD_OPENCL FALSE)
set(OPENMMDPD_CUDA FALSE)
if(NOT OPENMM_OPENCL_LIBRARY OR NOT EXISTS "${OPENMM_INCLUDE_DIR}/openmm/opencl/OpenCLPlatform.h")
  message(STATUS "OpenMM at ${OPENMM_DIR} has no OpenCL platform: not building the OpenCL kernels")
else()
  set(OPENMMDPD_OPENCL TRUE)
endif()
if(NOT OPENMM_CUDA_LIBRARY OR NOT EXISTS "${OPENMM_INCLUDE_DIR}/openmm/cuda/CudaPlatform.h")
  message(STATUS "OpenMM at ${OPENMM_DIR} has no CUDA platform: not building the CUDA kernels")
else()
  set(OPENMMDPD_CUDA TRUE)
endif()
if(NOT OPENMMDPD_OPENCL AND NOT OPENMMDPD_CUDA)
  return()
endif()

# The device code (platforms/common/kernels/*.cc) goes into the libraries as strings, compiled
# at run time by the platform (ComputeContext::compileProgram).
file(GLOB COMMON_KERNELS CONFIGURE_DEPENDS "${CMAKE_SOURCE_DIR}/platforms/common/kernels/*.cc")
set(KERNEL_SOURCES_DIR "${CMAKE_BINARY_DIR}/platforms/common")
add_custom_command(
  OUTPUT "${KERNEL_SOURCES_DIR}/CommonDPDKernelSources.cpp" "${KERNEL_SOURCES_DIR}/CommonDPDKernelSources.h"
  COMMAND ${CMAKE_COMMAND} -E make_directory "${KERNEL_SOURCES_DIR}"
  COMMAND ${CMAKE_COMMAND} "-DKERNEL_DIR=${CMAKE_SOURCE_DIR}/platforms/common/kernels" "-DOUTPUT_DIR=${KERNEL_SOURCES_DIR}"
          -P "${CMAKE_SOURCE_DIR}/cmake/EncodeKernelSources.cmake"
  DEPENDS ${COMMON_KERNELS} "${CMAKE_SOURCE_DIR}/cmake/EncodeKernelSources.cmake"
  COMMENT "Encoding the common kernel sources")
file(GLOB COMMON_SOURCES CONFIGURE_DEPENDS "${CMAKE_SOURCE_DIR}/platforms/common/src/*.cpp")
add_library(OpenMMDPDCommon STATIC ${COMMON_SOURCES} "${KERNEL_SOURCES_DIR}/CommonDPDKernelSources.cpp")
target_include_directories(OpenMMDPDCommon PUBLIC "${CMAKE_SOURCE_DIR}/platforms/common/include" PRIVATE "${KERNEL_SOURCES_DIR}")
target_link_libraries(OpenMMDPDCommon PUBLIC OpenMMDPDCore)
# Whole: a plugin also exports what only the tests call (drawDevicePairRandom).
set(OPENMMDPD_WHOLE_COMMON -Wl,--whole-archive OpenMMDPDCommon -Wl,--no-whole-archive OpenMMDPDCore)

if(OPENMMDPD_OPENCL)
  add_library(OpenMMDPDOpenCL SHARED platforms/opencl/src/OpenCLDPDKernelFactory.cpp)
  target_include_directories(OpenMMDPDOpenCL PUBLIC "${CMAKE_SOURCE_DIR}/platforms/opencl/include" PRIVATE "${OPENMM_INCLUDE_DIR}/openmm/opencl")
  target_link_libraries(OpenMMDPDOpenCL PRIVATE ${OPENMMDPD_WHOLE_COMMON} "${OPENMM_OPENCL_LIBRARY}")
  set_target_properties(OpenMMDPDOpenCL PROPERTIES
    BUILD_RPATH "$ORIGIN;${OPENMM_PLUGIN_DIR}" INSTALL_RPATH "$ORIGIN;${OPENMM_PLUGIN_DIR}")
  list(APPEND OPENMMDPD_GPU_PLUGINS OpenMMDPDOpenCL)
  message(STATUS "Building the OpenCL kernels against ${OPENMM_OPENCL_LIBRARY}")
endif()
if(OPENMMDPD_CUDA)
  add_library(OpenMMDPDCUDA SHARED platforms/cuda/src/CudaDPDKernelFactory.cpp)
  target_include_directories(OpenMMDPDCUDA PUBLIC "${CMAKE_SOURCE_DIR}/platforms/cuda/include" PRIVATE "${OPENMM_INCLUDE_DIR}/openmm/cuda")
  target_link_libraries(OpenMMDPDCUDA PRIVATE ${OPENMMDPD_WHOLE_COMMON} "${OPENMM_CUDA_LIBRARY}")
  set_target_properties(OpenMMDPDCUDA PROPERTIES
    BUILD_RPATH "$ORIGIN;${OPENMM_PLUGIN_DIR}" INSTALL_RPATH "$ORIGIN;${OPENMM_PLUGIN_DIR}")
  list(APPEND OPENMMDPD_GPU_PLUGINS OpenMMDPDCUDA)
  message(STATUS "Building the CUDA kernels against ${OPENMM_CUDA_LIBRARY} (they run only where a CUDA driver is)")
endif()
