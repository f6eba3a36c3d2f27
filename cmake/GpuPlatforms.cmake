# --- the GPU platforms: kernels written once on OpenMM's ComputeContext (platforms/common), with
# thin factories for OpenCL and CUDA, each built where the OpenMM install has that platform ---
if(NOT OPENMMDPD_BUILD_GPU)
  return()
endif()
# Only OpenMM's platform libraries and their Platform headers are needed to build: the kernels
# are compiled at run time by the platform (the OpenCL ICD or the CUDA driver, where they exist).
# OpenMM's platform `name` (OpenCL, CUDA) is library OpenMM<name> with header
# openmm/<name in lower case>/<prefix>Platform.h; OPENMMDPD_<NAME> says whether it is there.
function(openmmdpd_find_gpu_platform name prefix)
  string(TOUPPER "${name}" upper)
  string(TOLOWER "${name}" lower)
  find_library(OPENMM_${upper}_LIBRARY OpenMM${name} HINTS "${OPENMM_PLUGIN_DIR}" NO_DEFAULT_PATH)
  if(OPENMM_${upper}_LIBRARY AND EXISTS "${OPENMM_INCLUDE_DIR}/openmm/${lower}/${prefix}Platform.h")
    set(OPENMMDPD_${upper} TRUE PARENT_SCOPE)
  else()
    set(OPENMMDPD_${upper} FALSE PARENT_SCOPE)
    message(STATUS "OpenMM at ${OPENMM_DIR} has no ${name} platform: not building the ${name} kernels")
  endif()
endfunction()
openmmdpd_find_gpu_platform(OpenCL OpenCL)
openmmdpd_find_gpu_platform(CUDA Cuda)
if(NOT OPENMMDPD_OPENCL AND NOT OPENMMDPD_CUDA)
  return()
endif()

# The device code (platforms/common/kernels/*.cc) goes into the libraries as strings, compiled
# at run time by the platform (ComputeContext::compileProgram).
file(GLOB COMMON_KERNELS CONFIGURE_DEPENDS "${CMAKE_SOURCE_DIR}/platforms/common/kernels/*.cc")
set(PAIR_FORMULAS "${CMAKE_SOURCE_DIR}/platforms/core/include/openmmdpd/PairFormulas.h")
set(KERNEL_SOURCES_DIR "${CMAKE_BINARY_DIR}/platforms/common")
add_custom_command(
  OUTPUT "${KERNEL_SOURCES_DIR}/CommonDPDKernelSources.cpp" "${KERNEL_SOURCES_DIR}/CommonDPDKernelSources.h"
  COMMAND ${CMAKE_COMMAND} -E make_directory "${KERNEL_SOURCES_DIR}"
  COMMAND ${CMAKE_COMMAND} "-DKERNEL_DIR=${CMAKE_SOURCE_DIR}/platforms/common/kernels" "-DFORMULAS_FILE=${PAIR_FORMULAS}"
          "-DOUTPUT_DIR=${KERNEL_SOURCES_DIR}" -P "${CMAKE_SOURCE_DIR}/cmake/EncodeKernelSources.cmake"
  DEPENDS ${COMMON_KERNELS} "${PAIR_FORMULAS}" "${CMAKE_SOURCE_DIR}/cmake/EncodeKernelSources.cmake"
  COMMENT "Encoding the common kernel sources")
file(GLOB COMMON_SOURCES CONFIGURE_DEPENDS "${CMAKE_SOURCE_DIR}/platforms/common/src/*.cpp")
add_library(OpenMMDPDCommon STATIC ${COMMON_SOURCES} "${KERNEL_SOURCES_DIR}/CommonDPDKernelSources.cpp")
target_include_directories(OpenMMDPDCommon PUBLIC "${CMAKE_SOURCE_DIR}/platforms/common/include" PRIVATE "${KERNEL_SOURCES_DIR}")
target_link_libraries(OpenMMDPDCommon PUBLIC OpenMMDPDCore)
# Whole: a plugin also exports what only the tests call (drawDevicePairRandom).
set(OPENMMDPD_WHOLE_COMMON -Wl,--whole-archive OpenMMDPDCommon -Wl,--no-whole-archive OpenMMDPDCore)

# One platform's plugin OpenMMDPD<name>: its thin factory (platforms/<name in lower case>/src/
# <prefix>DPDKernelFactory.cpp) over the common kernels, against OpenMM's platform library.
function(openmmdpd_add_gpu_plugin name prefix note)
  string(TOUPPER "${name}" upper)
  string(TOLOWER "${name}" lower)
  set(target OpenMMDPD${name})
  add_library(${target} SHARED platforms/${lower}/src/${prefix}DPDKernelFactory.cpp)
  target_include_directories(${target} PUBLIC "${CMAKE_SOURCE_DIR}/platforms/${lower}/include")
  target_include_directories(${target} SYSTEM PRIVATE "${OPENMM_INCLUDE_DIR}/openmm/${lower}")
  target_link_libraries(${target} PRIVATE ${OPENMMDPD_WHOLE_COMMON} "${OPENMM_${upper}_LIBRARY}")
  set_target_properties(${target} PROPERTIES
    BUILD_RPATH "$ORIGIN;${OPENMM_PLUGIN_DIR}" INSTALL_RPATH "$ORIGIN;${OPENMM_PLUGIN_DIR}")
  set(OPENMMDPD_GPU_PLUGINS ${OPENMMDPD_GPU_PLUGINS} ${target} PARENT_SCOPE)
  message(STATUS "Building the ${name} kernels against ${OPENMM_${upper}_LIBRARY}${note}")
endfunction()
if(OPENMMDPD_OPENCL)
  openmmdpd_add_gpu_plugin(OpenCL OpenCL "")
endif()
if(OPENMMDPD_CUDA)
  openmmdpd_add_gpu_plugin(CUDA Cuda " (they run only where a CUDA driver is)")
endif()
