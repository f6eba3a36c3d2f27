#ifndef OPENMMDPD_DPDSOFTREPULSIONFORCEIMPL_H_
#define OPENMMDPD_DPDSOFTREPULSIONFORCEIMPL_H_

#include "openmmdpd/DPDSoftRepulsionForce.h"
#include "openmm/Kernel.h"
#include "openmmdpd/internal/PairVirialForceImpl.h"

namespace DPDPlugin {

class DPDSoftRepulsionForceImpl : public PairVirialForceImpl {
public:
    explicit DPDSoftRepulsionForceImpl(const DPDSoftRepulsionForce& owner) : owner(owner) {}
    void initialize(OpenMM::ContextImpl& context) override;
    const DPDSoftRepulsionForce& getOwner() const override { return owner; }
    /**
     * Nothing to update between steps.  (ForceImpl's default reports the forces as
     * invalidated, which would make integrators that carry forces recompute them every step.)
     */
    void updateContextState(OpenMM::ContextImpl& context, bool& forcesInvalid) override {}
    double calcForcesAndEnergy(OpenMM::ContextImpl& context, bool includeForces, bool includeEnergy, int groups) override;
    std::map<std::string, double> getDefaultParameters() override { return {}; }
    std::vector<std::string> getKernelNames() override;
    void updateParametersInContext(OpenMM::ContextImpl& context);
    /** The platform's kernel (integrators that evaluate this force from their own pair list use it). */
    OpenMM::Kernel& getKernel() { return kernel; }
    std::array<double, 6> computeVirial(OpenMM::ContextImpl& context) override;
    /** Throw unless the force is consistent with the System (particle indices, box). */
    static void validate(const DPDSoftRepulsionForce& force, const OpenMM::System& system);

private:
    const DPDSoftRepulsionForce& owner;
    OpenMM::Kernel kernel;
};

} // namespace DPDPlugin

#endif
