#include "openmm/Platform.h"
#include <gtest/gtest.h>

extern "C" void registerDPDReferenceKernelFactories();
#if OPENMMDPD_HAVE_CPU
extern "C" void registerDPDCpuKernelFactories();
#endif
#if OPENMMDPD_HAVE_OPENCL
extern "C" void registerDPDOpenCLKernelFactories();
#endif
#if OPENMMDPD_HAVE_CUDA
extern "C" void registerDPDCudaKernelFactories();
#endif

int main(int argc, char** argv) {
    ::testing::InitGoogleTest(&argc, argv);
    // OpenMM's own plugins (the CPU platform) first, then our kernels on top of them.  From the
    // OpenMM built against: an upstream OpenMM's default folder is /usr/local/openmm/lib/plugins
    // unless OPENMM_PLUGIN_DIR is set.
    OpenMM::Platform::loadPluginsFromDirectory(OPENMMDPD_OPENMM_PLUGIN_DIR);
    registerDPDReferenceKernelFactories();
#if OPENMMDPD_HAVE_CPU
    registerDPDCpuKernelFactories();
#endif
#if OPENMMDPD_HAVE_OPENCL
    registerDPDOpenCLKernelFactories();
#endif
#if OPENMMDPD_HAVE_CUDA
    registerDPDCudaKernelFactories();
#endif
    return RUN_ALL_TESTS();
}
