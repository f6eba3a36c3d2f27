#include "ThreadPoolExecutor.h"
#include "openmmdpd/DPDStepKernel.h"
#include "openmmdpd/SoftRepulsionKernel.h"
#include "CpuPlatform.h"
#include "openmm/KernelFactory.h"
#include "openmm/OpenMMException.h"
#include "openmm/Platform.h"

using namespace DPDPlugin;
using namespace OpenMM;

namespace {

class CpuDPDKernelFactory : public KernelFactory {
public:
    KernelImpl* createKernelImpl(std::string name, const Platform& platform, ContextImpl& context) const override {
        for (const std::string& known : DPDStepKernel::names())
            if (name == known)
                return new DPDStepKernel(name, platform, std::unique_ptr<ParallelExecutor>(new ThreadPoolExecutor(CpuPlatform::getPlatformData(context).threads)));
        if (name == CalcDPDSoftRepulsionForceKernel::Name())
            return new SoftRepulsionKernel(name, platform, std::unique_ptr<ParallelExecutor>(new ThreadPoolExecutor(CpuPlatform::getPlatformData(context).threads)));
        throw OpenMMException("openmm-dpd CPU plugin: unknown kernel '" + name + "'");
    }
};

} // namespace

extern "C" OPENMM_EXPORT void registerDPDCpuKernelFactories() {
    Platform& platform = Platform::getPlatformByName("CPU");
    KernelFactory* factory = new CpuDPDKernelFactory();
    for (const std::string& name : DPDStepKernel::names())
        platform.registerKernelFactory(name, factory);
    platform.registerKernelFactory(CalcDPDSoftRepulsionForceKernel::Name(), factory);
}

extern "C" OPENMM_EXPORT void registerKernelFactories() {
    // Without the CPU platform (e.g. no AVX-capable build) there is nothing to add to.
    for (int i = 0; i < Platform::getNumPlatforms(); i++)
        if (Platform::getPlatform(i).getName() == "CPU")
            registerDPDCpuKernelFactories();
}

// This plugin adds no platform; without its own registerPlatforms() the loader would find
// libOpenMMCPU's through the dependency chain and register the CPU platform twice.
extern "C" OPENMM_EXPORT void registerPlatforms() {
}
