#include "openmmdpd/DPDStepKernel.h"
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
        KernelImpl* kernel = createDPDKernel(name, platform, [] { return std::unique_ptr<ParallelExecutor>(new SerialExecutor()); });
        if (kernel != nullptr)
            return kernel;
        throw OpenMMException("openmm-dpd Reference plugin: unknown kernel '" + name + "'");
    }
};

} // namespace

extern "C" OPENMM_EXPORT void registerDPDReferenceKernelFactories() {
    Platform& platform = Platform::getPlatformByName("Reference");
    KernelFactory* factory = new ReferenceDPDKernelFactory();
    for (const std::string& name : dpdKernelNames())
        platform.registerKernelFactory(name, factory);
}

extern "C" OPENMM_EXPORT void registerKernelFactories() {
    registerDPDReferenceKernelFactories();
}

// This plugin adds no platform; it exports its own empty registerPlatforms() so that the
// loader does not find another library's (and register that platform a second time).
extern "C" OPENMM_EXPORT void registerPlatforms() {
}
