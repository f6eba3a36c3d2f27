#include "ThreadPoolExecutor.h"
#include "openmmdpd/DPDStepKernel.h"
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
        ThreadPool& threads = CpuPlatform::getPlatformData(context).threads;
        KernelImpl* kernel = createDPDKernel(name, platform, [&] { return std::unique_ptr<ParallelExecutor>(new ThreadPoolExecutor(threads)); });
        if (kernel != nullptr)
            return kernel;
        throw OpenMMException("openmm-dpd CPU plugin: unknown kernel '" + name + "'");
    }
};

} // namespace

extern "C" OPENMM_EXPORT void registerDPDCpuKernelFactories() {
    Platform& platform = Platform::getPlatformByName("CPU");
    KernelFactory* factory = new CpuDPDKernelFactory();
    for (const std::string& name : dpdKernelNames())
        platform.registerKernelFactory(name, factory);
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
