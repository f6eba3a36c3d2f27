// The OpenCL platform's kernels: the common ones (platforms/common) on its OpenCLContext.
#include "openmmdpd/OpenCLDPDKernelFactory.h"
#include "openmmdpd/CommonDPDKernelFactory.h"
#include "openmmdpd/OpenMMVersionCheck.h"
#include "OpenCLPlatform.h"

using namespace DPDPlugin;
using namespace OpenMM;

ComputeContext& DPDPlugin::getOpenCLComputeContext(ContextImpl& context) {
    return computeContextOf<OpenCLPlatform::PlatformData>(context, "openmm-dpd OpenCL plugin");
}

/** Registers the kernels with OpenMM's OpenCL platform, if OpenMM has one (no OpenCL library or device: nothing). */
extern "C" OPENMM_EXPORT void registerDPDOpenCLKernelFactories() {
    CommonDPDKernelFactory::registerWith("OpenCL", "openmm-dpd OpenCL plugin", getOpenCLComputeContext);
}

extern "C" OPENMM_EXPORT void registerKernelFactories() {
    if (pluginMatchesRunningOpenMM("openmm-dpd OpenCL plugin"))
        registerDPDOpenCLKernelFactories();
}

// This plugin adds no platform (see the Reference plugin's factory).
extern "C" OPENMM_EXPORT void registerPlatforms() {
}
