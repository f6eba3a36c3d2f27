// The OpenCL platform's kernels: the common ones (platforms/common) on the OpenCLContext.
#include "openmmdpd/OpenCLDPDKernelFactory.h"
#include "openmmdpd/CommonDPDKernels.h"
#include "openmmdpd/OpenMMVersionCheck.h"
#include "OpenCLPlatform.h"
#include "openmm/KernelFactory.h"
#include "openmm/OpenMMException.h"
#include "openmm/internal/ContextImpl.h"
#include "openmm/internal/windowsExport.h"

using namespace DPDPlugin;
using namespace OpenMM;

/*
 * OpenCLContext.h is not included: it pulls in Lepton's headers, which Debian's OpenMM 7.7 does not
 * ship.  OpenCLContext derives from ComputeContext alone (OpenMM 7.7 to 8.5), so its address is
 * that of its ComputeContext; the particle count checks that the object is the one expected.
 */
ComputeContext& DPDPlugin::getOpenCLComputeContext(ContextImpl& context) {
    OpenCLContext* device = static_cast<OpenCLPlatform::PlatformData*>(context.getPlatformData())->contexts[0];
    ComputeContext& cc = *reinterpret_cast<ComputeContext*>(device);
    if (cc.getNumAtoms() != context.getSystem().getNumParticles())
        throw OpenMMException("openmm-dpd OpenCL plugin: the OpenCL platform's data is not laid out as expected; rebuild "
                              "openmm-dpd against the OpenMM it runs with");
    return cc;
}

namespace {

class OpenCLDPDKernelFactory : public KernelFactory {
public:
    KernelImpl* createKernelImpl(std::string name, const Platform& platform, ContextImpl& context) const override {
        ComputeContext& cc = getOpenCLComputeContext(context);
        if (name == IntegrateDPDVVStepKernel::Name())
            return new CommonIntegrateDPDVVStepKernel(name, platform, cc);
        if (name == IntegrateShardlowStepKernel::Name())
            return new CommonIntegrateShardlowStepKernel(name, platform, cc);
        if (name == IntegrateLoweAndersenStepKernel::Name())
            return new CommonIntegrateLoweAndersenStepKernel(name, platform, cc);
        if (name == CalcDPDSoftRepulsionForceKernel::Name())
            return new CommonSoftRepulsionKernel(name, platform, cc);
        throw OpenMMException("openmm-dpd OpenCL plugin: unknown kernel '" + name + "'");
    }
};

} // namespace

/** Registers the kernels with OpenMM's OpenCL platform, if OpenMM has one (no OpenCL library or device: nothing). */
extern "C" OPENMM_EXPORT void registerDPDOpenCLKernelFactories() {
    Platform* platform;
    try {
        platform = &Platform::getPlatformByName("OpenCL");
    }
    catch (const OpenMMException&) {
        return;
    }
    KernelFactory* factory = new OpenCLDPDKernelFactory();
    platform->registerKernelFactory(IntegrateDPDVVStepKernel::Name(), factory);
    platform->registerKernelFactory(IntegrateShardlowStepKernel::Name(), factory);
    platform->registerKernelFactory(IntegrateLoweAndersenStepKernel::Name(), factory);
    platform->registerKernelFactory(CalcDPDSoftRepulsionForceKernel::Name(), factory);
}

extern "C" OPENMM_EXPORT void registerKernelFactories() {
    if (pluginMatchesRunningOpenMM("openmm-dpd OpenCL plugin"))
        registerDPDOpenCLKernelFactories();
}

// This plugin adds no platform (see the Reference plugin's factory).
extern "C" OPENMM_EXPORT void registerPlatforms() {
}
