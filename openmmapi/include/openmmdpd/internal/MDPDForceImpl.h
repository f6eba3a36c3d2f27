#ifndef OPENMMDPD_MDPDFORCEIMPL_H_
#define OPENMMDPD_MDPDFORCEIMPL_H_

#include "openmmdpd/MDPDForce.h"
#include "openmmdpd/internal/PairVirialForceImpl.h"
#include "openmm/Kernel.h"

namespace DPDPlugin {

class MDPDForceImpl : public PairVirialForceImpl {
public:
    explicit MDPDForceImpl(const MDPDForce& owner) : owner(owner) {}
    void initialize(OpenMM::ContextImpl& context) override;
    const MDPDForce& getOwner() const override { return owner; }
    /** Nothing to update between steps (the default would invalidate carried forces every step). */
    void updateContextState(OpenMM::ContextImpl& context, bool& forcesInvalid) override {}
    double calcForcesAndEnergy(OpenMM::ContextImpl& context, bool includeForces, bool includeEnergy, int groups) override;
    std::map<std::string, double> getDefaultParameters() override { return {}; }
    std::vector<std::string> getKernelNames() override;
    std::array<double, 6> computeVirial(OpenMM::ContextImpl& context) override;
    /** The platform's kernel (integrators that add this force in their own pair pass use it). */
    OpenMM::Kernel& getKernel() { return kernel; }
    void updateParametersInContext(OpenMM::ContextImpl& context);
    /** Throw unless the force is consistent with the System (particle indices, types, box). */
    static void validate(const MDPDForce& force, const OpenMM::System& system);

private:
    const MDPDForce& owner;
    OpenMM::Kernel kernel;
};

} // namespace DPDPlugin

#endif
