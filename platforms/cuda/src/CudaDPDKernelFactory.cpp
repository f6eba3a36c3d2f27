// The CUDA platform's kernels: the common ones (platforms/common) on its CudaContext.
#include "openmmdpd/CudaDPDKernelFactory.h"
#include "openmmdpd/CommonDPDKernelFactory.h"
#include "openmmdpd/OpenMMVersionCheck.h"
#include "CudaPlatform.h"

using namespace DPDPlugin;
using namespace OpenMM;

ComputeContext& DPDPlugin::getCudaComputeContext(ContextImpl& context) {
    return computeContextOf<CudaPlatform::PlatformData>(context, "openmm-dpd CUDA plugin");
}

/** Registers the kernels with OpenMM's CUDA platform, if OpenMM has one (no CUDA library or device: nothing). */
extern "C" OPENMM_EXPORT void registerDPDCudaKernelFactories() {
    CommonDPDKernelFactory::registerWith("CUDA", "openmm-dpd CUDA plugin", getCudaComputeContext);
}

extern "C" OPENMM_EXPORT void registerKernelFactories() {
    if (pluginMatchesRunningOpenMM("openmm-dpd CUDA plugin"))
        registerDPDCudaKernelFactories();
}

// This plugin adds no platform (see the Reference plugin's factory).
extern "C" OPENMM_EXPORT void registerPlatforms() {
}
