#include "openmmdpd/CommonDPDKernelFactory.h"
#include "openmmdpd/CommonDPDKernels.h"
#include "openmmdpd/CommonMDPDKernel.h"
#include "openmm/Platform.h"

using namespace DPDPlugin;
using namespace OpenMM;

KernelImpl* CommonDPDKernelFactory::createKernelImpl(std::string name, const Platform& platform, ContextImpl& context) const {
    ComputeContext& cc = find(context);
    if (name == IntegrateDPDVVStepKernel::Name())
        return new CommonIntegrateDPDVVStepKernel(name, platform, cc);
    if (name == IntegrateShardlowStepKernel::Name())
        return new CommonIntegrateShardlowStepKernel(name, platform, cc);
    if (name == IntegrateLoweAndersenStepKernel::Name())
        return new CommonIntegrateLoweAndersenStepKernel(name, platform, cc);
    if (name == IntegrateStaggeredDPDStepKernel::Name())
        return new CommonIntegrateStaggeredDPDStepKernel(name, platform, cc);
    if (name == IntegrateDenOtterClarkeStepKernel::Name())
        return new CommonIntegrateDenOtterClarkeStepKernel(name, platform, cc);
    if (name == IntegrateEDPDStepKernel::Name())
        return new CommonIntegrateEDPDStepKernel(name, platform, cc);
    if (name == CalcDPDSoftRepulsionForceKernel::Name())
        return new CommonSoftRepulsionKernel(name, platform, cc);
    if (name == CalcMDPDForceKernel::Name())
        return new CommonMDPDKernel(name, platform, cc);
    throw OpenMMException(plugin + ": unknown kernel '" + name + "'");
}

void CommonDPDKernelFactory::registerWith(const std::string& platformName, const std::string& plugin, ContextFinder find) {
    Platform* platform;
    try {
        platform = &Platform::getPlatformByName(platformName);
    }
    catch (const OpenMMException&) {
        return;
    }
    KernelFactory* factory = new CommonDPDKernelFactory(plugin, find);
    for (const std::string& name : {IntegrateDPDVVStepKernel::Name(), IntegrateShardlowStepKernel::Name(),
                                    IntegrateLoweAndersenStepKernel::Name(), IntegrateDenOtterClarkeStepKernel::Name(),
                                    IntegrateStaggeredDPDStepKernel::Name(), IntegrateEDPDStepKernel::Name(),
                                    CalcDPDSoftRepulsionForceKernel::Name(),
                                    CalcMDPDForceKernel::Name()})
        platform->registerKernelFactory(name, factory);
}
