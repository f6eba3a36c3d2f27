#ifndef OPENMMDPD_COMMONDPDKERNELFACTORY_H_
#define OPENMMDPD_COMMONDPDKERNELFACTORY_H_

#include "openmm/KernelFactory.h"
#include "openmm/OpenMMException.h"
#include "openmm/common/ComputeContext.h"
#include "openmm/internal/ContextImpl.h"
#include <string>

namespace DPDPlugin {

/**
 * The kernels of platforms/common on one GPU platform; a platform's plugin says only how to
 * find its ComputeContext in a Context and under which name to register.
 */
class CommonDPDKernelFactory : public OpenMM::KernelFactory {
public:
    using ContextFinder = OpenMM::ComputeContext& (*)(OpenMM::ContextImpl&);
    CommonDPDKernelFactory(const std::string& plugin, ContextFinder find) : plugin(plugin), find(find) {}
    OpenMM::KernelImpl* createKernelImpl(std::string name, const OpenMM::Platform& platform,
                                         OpenMM::ContextImpl& context) const override;
    /** Registers the kernels with OpenMM's platform `platformName`, if OpenMM has it (else nothing). */
    static void registerWith(const std::string& platformName, const std::string& plugin, ContextFinder find);

private:
    std::string plugin;  // "openmm-dpd <platform> plugin", for messages
    ContextFinder find;
};

/**
 * The ComputeContext of a Context on a GPU platform, from its PlatformData (OpenCL's or CUDA's).
 * Their Context headers are not included: they pull in Lepton's headers, which Debian's OpenMM
 * 7.7 does not ship.  OpenCLContext and CudaContext derive from ComputeContext alone (OpenMM 7.7
 * to 8.5), so a device context's address is that of its ComputeContext; the particle count
 * checks that the object is the one expected.
 */
template <class PlatformData>
OpenMM::ComputeContext& computeContextOf(OpenMM::ContextImpl& context, const std::string& plugin) {
    auto* device = static_cast<PlatformData*>(context.getPlatformData())->contexts[0];
    OpenMM::ComputeContext& cc = *reinterpret_cast<OpenMM::ComputeContext*>(device);
    if (cc.getNumAtoms() != context.getSystem().getNumParticles())
        throw OpenMM::OpenMMException(plugin + ": the platform's data is not laid out as expected; rebuild "
                                      "openmm-dpd against the OpenMM it runs with");
    return cc;
}

} // namespace DPDPlugin

#endif
