#ifndef OPENMMDPD_REFERENCESOFTREPULSIONKERNEL_H_
#define OPENMMDPD_REFERENCESOFTREPULSIONKERNEL_H_

#include "openmmdpd/DPDKernels.h"
#include "openmmdpd/PairParameters.h"
#include <memory>
#include <set>
#include <utility>

namespace DPDPlugin {

/** DPDSoftRepulsionForce on the Reference platform: a plain loop over the pairs of a cell list. */
class ReferenceSoftRepulsionKernel : public CalcDPDSoftRepulsionForceKernel {
public:
    ReferenceSoftRepulsionKernel(std::string name, const OpenMM::Platform& platform) : CalcDPDSoftRepulsionForceKernel(name, platform) {}
    void initialize(const OpenMM::System& system, const DPDSoftRepulsionForce& force) override;
    double execute(OpenMM::ContextImpl& context, bool includeForces, bool includeEnergy) override;
    void copyParametersToContext(OpenMM::ContextImpl& context, const DPDSoftRepulsionForce& force) override;
    std::array<double, 6> computeVirial(OpenMM::ContextImpl& context) override;

private:
    void setParameters(const DPDSoftRepulsionForce& force);
    /** body(pair, type pair, r) for every pair the force acts on (within its cutoff, not excluded). */
    template <class Body>
    void forEachPair(OpenMM::ContextImpl& context, Body body) const;
    int numParticles = 0;
    bool periodic = false;
    std::unique_ptr<TypePairTable> table;
    std::set<std::pair<int, int>> exclusions;  // (lower, higher) index
};

} // namespace DPDPlugin

#endif
