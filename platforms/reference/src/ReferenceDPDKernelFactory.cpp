#include "openmmdpd/DPDVVStepKernel.h"
#include "openmm/KernelFactory.h"
#include "openmm/OpenMMException.h"
#include "openmm/Platform.h"
#include "openmm/internal/windowsExport.h"

using namespace DPDPlugin;
using namespace OpenMM;

namespace {

class ReferenceDPDKernelFactory : public KernelFactory {
public:
    KernelImpl* createKernelImpl(std::string name, const Platform& platform, ContextImpl& context) const override {
        if (name == IntegrateDPDVVStepKernel::Name())
            return new DPDVVStepKernel(name, platform, std::unique_ptr<ParallelExecutor>(new SerialExecutor()));
        throw OpenMMException("openmm-dpd Reference plugin: unknown kernel '" + name + "'");
    }
};

} // namespace

extern "C" OPENMM_EXPORT void registerDPDReferenceKernelFactories() {
    Platform& platform = Platform::getPlatformByName("Reference");
    platform.registerKernelFactory(IntegrateDPDVVStepKernel::Name(), new ReferenceDPDKernelFactory());
}

extern "C" OPENMM_EXPORT void registerKernelFactories() {
    registerDPDReferenceKernelFactories();
}

// This plugin adds no platform; it exports its own empty registerPlatforms() so that the
// loader does not find another library's (and register that platform a second time).
extern "C" OPENMM_EXPORT void registerPlatforms() {
}
