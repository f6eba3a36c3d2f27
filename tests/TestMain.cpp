#include "openmm/Platform.h"
#include <gtest/gtest.h>

extern "C" void registerDPDReferenceKernelFactories();
#if OPENMMDPD_HAVE_CPU
extern "C" void registerDPDCpuKernelFactories();
#endif

int main(int argc, char** argv) {
    ::testing::InitGoogleTest(&argc, argv);
    // OpenMM's own plugins (the CPU platform) first, then our kernels on top of them.
    OpenMM::Platform::loadPluginsFromDirectory(OpenMM::Platform::getDefaultPluginsDirectory());
    registerDPDReferenceKernelFactories();
#if OPENMMDPD_HAVE_CPU
    registerDPDCpuKernelFactories();
#endif
    return RUN_ALL_TESTS();
}
