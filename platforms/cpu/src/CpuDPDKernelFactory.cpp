#include "openmmdpd/CpuDPDKernels.h"
#include "openmmdpd/MDPDKernel.h"
#include "openmmdpd/SoftRepulsionKernel.h"
#include "CpuPlatform.h"
#include "openmmdpd/OpenMMVersionCheck.h"
#include "openmm/KernelFactory.h"
#include "openmm/OpenMMException.h"
#include "openmm/Platform.h"

using namespace DPDPlugin;
using namespace OpenMM;

namespace {

const std::vector<std::string> kernelNames = {
    IntegrateDPDVVStepKernel::Name(), IntegrateShardlowStepKernel::Name(), IntegrateLoweAndersenStepKernel::Name(),
    IntegrateEDPDStepKernel::Name(), IntegrateStaggeredDPDStepKernel::Name(), IntegrateDenOtterClarkeStepKernel::Name(),
    CalcDPDSoftRepulsionForceKernel::Name(), CalcMDPDForceKernel::Name()};

class CpuDPDKernelFactory : public KernelFactory {
public:
    KernelImpl* createKernelImpl(std::string name, const Platform& platform, ContextImpl& context) const override {
        ThreadPool& threads = CpuPlatform::getPlatformData(context).threads;
        if (name == IntegrateDPDVVStepKernel::Name())
            return new CpuIntegrateDPDVVStepKernel(name, platform, threads);
        if (name == IntegrateShardlowStepKernel::Name())
            return new CpuIntegrateShardlowStepKernel(name, platform, threads);
        if (name == IntegrateLoweAndersenStepKernel::Name())
            return new CpuIntegrateLoweAndersenStepKernel(name, platform, threads);
        if (name == IntegrateEDPDStepKernel::Name())
            return new CpuIntegrateEDPDStepKernel(name, platform, threads);
        if (name == IntegrateStaggeredDPDStepKernel::Name())
            return new CpuIntegrateStaggeredDPDStepKernel(name, platform, threads);
        if (name == IntegrateDenOtterClarkeStepKernel::Name())
            return new CpuIntegrateDenOtterClarkeStepKernel(name, platform, threads);
        if (name == CalcDPDSoftRepulsionForceKernel::Name())
            return new SoftRepulsionKernel(name, platform, std::unique_ptr<ParallelExecutor>(new ThreadPoolExecutor(threads)));
        if (name == CalcMDPDForceKernel::Name())
            return new MDPDKernel(name, platform, std::unique_ptr<ParallelExecutor>(new ThreadPoolExecutor(threads)));
        throw OpenMMException("openmm-dpd CPU plugin: unknown kernel '" + name + "'");
    }
};

} // namespace

extern "C" OPENMM_EXPORT void registerDPDCpuKernelFactories() {
    Platform& platform = Platform::getPlatformByName("CPU");
    KernelFactory* factory = new CpuDPDKernelFactory();
    for (const std::string& name : kernelNames)
        platform.registerKernelFactory(name, factory);
}

extern "C" OPENMM_EXPORT void registerKernelFactories() {
    if (!pluginMatchesRunningOpenMM("openmm-dpd CPU plugin"))
        return;
    // Without the CPU platform (e.g. no AVX-capable build) there is nothing to add to.
    for (int i = 0; i < Platform::getNumPlatforms(); i++)
        if (Platform::getPlatform(i).getName() == "CPU")
            registerDPDCpuKernelFactories();
}

// This plugin adds no platform; without its own registerPlatforms() the loader would find
// libOpenMMCPU's through the dependency chain and register the CPU platform twice.
extern "C" OPENMM_EXPORT void registerPlatforms() {
}
