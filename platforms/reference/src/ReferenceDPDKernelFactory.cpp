#include "openmmdpd/ReferenceDPDKernels.h"
#include "openmmdpd/ReferenceMDPDKernel.h"
#include "openmmdpd/ReferenceSoftRepulsionKernel.h"
#include "openmmdpd/OpenMMVersionCheck.h"
#include "openmm/KernelFactory.h"
#include "openmm/OpenMMException.h"
#include "openmm/Platform.h"
#include "openmm/internal/windowsExport.h"

using namespace DPDPlugin;
using namespace OpenMM;

namespace {

const std::vector<std::string> kernelNames = {
    IntegrateDPDVVStepKernel::Name(), IntegrateShardlowStepKernel::Name(), IntegrateLoweAndersenStepKernel::Name(),
    IntegrateEDPDStepKernel::Name(), IntegrateStaggeredDPDStepKernel::Name(), IntegrateDenOtterClarkeStepKernel::Name(),
    CalcDPDSoftRepulsionForceKernel::Name(), CalcMDPDForceKernel::Name()};

class ReferenceDPDKernelFactory : public KernelFactory {
public:
    KernelImpl* createKernelImpl(std::string name, const Platform& platform, ContextImpl& context) const override {
        if (name == IntegrateDPDVVStepKernel::Name())
            return new ReferenceIntegrateDPDVVStepKernel(name, platform);
        if (name == IntegrateShardlowStepKernel::Name())
            return new ReferenceIntegrateShardlowStepKernel(name, platform);
        if (name == IntegrateLoweAndersenStepKernel::Name())
            return new ReferenceIntegrateLoweAndersenStepKernel(name, platform);
        if (name == IntegrateEDPDStepKernel::Name())
            return new ReferenceIntegrateEDPDStepKernel(name, platform);
        if (name == IntegrateStaggeredDPDStepKernel::Name())
            return new ReferenceIntegrateStaggeredDPDStepKernel(name, platform);
        if (name == IntegrateDenOtterClarkeStepKernel::Name())
            return new ReferenceIntegrateDenOtterClarkeStepKernel(name, platform);
        if (name == CalcDPDSoftRepulsionForceKernel::Name())
            return new ReferenceSoftRepulsionKernel(name, platform);
        if (name == CalcMDPDForceKernel::Name())
            return new ReferenceMDPDKernel(name, platform);
        throw OpenMMException("openmm-dpd Reference plugin: unknown kernel '" + name + "'");
    }
};

} // namespace

extern "C" OPENMM_EXPORT void registerDPDReferenceKernelFactories() {
    Platform& platform = Platform::getPlatformByName("Reference");
    KernelFactory* factory = new ReferenceDPDKernelFactory();
    for (const std::string& name : kernelNames)
        platform.registerKernelFactory(name, factory);
}

extern "C" OPENMM_EXPORT void registerKernelFactories() {
    if (pluginMatchesRunningOpenMM("openmm-dpd Reference plugin"))
        registerDPDReferenceKernelFactories();
}

// This plugin adds no platform; it exports its own empty registerPlatforms() so that the
// loader does not find another library's (and register that platform a second time).
extern "C" OPENMM_EXPORT void registerPlatforms() {
}
