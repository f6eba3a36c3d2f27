#ifndef OPENMMDPD_REFERENCEMDPDKERNEL_H_
#define OPENMMDPD_REFERENCEMDPDKERNEL_H_

#include "openmmdpd/DPDKernels.h"
#include "openmmdpd/MDPDParameters.h"
#include "openmmdpd/ReferencePairList.h"
#include <memory>
#include <set>
#include <utility>

namespace DPDPlugin {

/**
 * MDPDForce on the Reference platform, as docs/theory/mdpd.md writes it: the pairs within
 * the cutoff, the local densities summed over them, then each pair's force.
 */
class ReferenceMDPDKernel : public CalcMDPDForceKernel {
public:
    ReferenceMDPDKernel(std::string name, const OpenMM::Platform& platform) : CalcMDPDForceKernel(name, platform) {}
    void initialize(const OpenMM::System& system, const MDPDForce& force) override;
    double execute(OpenMM::ContextImpl& context, bool includeForces, bool includeEnergy) override;
    void copyParametersToContext(OpenMM::ContextImpl& context, const MDPDForce& force) override;
    std::array<double, 6> computeVirial(OpenMM::ContextImpl& context) override;

private:
    /** A pair the force acts on: within its cutoff and not excluded. */
    struct Pair {
        ReferencePair pair;
        int typePair;
        double r;
    };
    /** The pairs at the Context's positions, and every particle's local density over them. */
    std::vector<Pair> findPairs(OpenMM::ContextImpl& context, std::vector<double>& density) const;
    /** The force on i along e of a pair, at these densities. */
    double pairForce(const Pair& p, const std::vector<double>& density) const;
    int numParticles = 0;
    bool periodic = false;
    std::unique_ptr<MDPDParameters> parameters;
    std::set<std::pair<int, int>> exclusions;  // (lower, higher) index
};

} // namespace DPDPlugin

#endif
