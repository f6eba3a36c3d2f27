#ifndef OPENMMDPD_SOFTREPULSIONKERNEL_H_
#define OPENMMDPD_SOFTREPULSIONKERNEL_H_

#include "openmmdpd/DPDKernels.h"
#include "openmmdpd/DPDPairCore.h"
#include "openmmdpd/ParallelExecutor.h"
#include "openmmdpd/PairSearch.h"
#include <algorithm>
#include <memory>
#include <vector>

namespace DPDPlugin {

/**
 * DPDSoftRepulsionForce on every platform: the thermostats' cell search finds the pairs,
 * each worker sums a range of cells into its own buffer, and the buffers are added to the
 * Context's forces in worker order.  Double precision throughout.
 */
class SoftRepulsionKernel : public CalcDPDSoftRepulsionForceKernel {
public:
    SoftRepulsionKernel(std::string name, const OpenMM::Platform& platform, std::unique_ptr<ParallelExecutor> executor) :
            CalcDPDSoftRepulsionForceKernel(name, platform), executor(std::move(executor)) {}
    void initialize(const OpenMM::System& system, const DPDSoftRepulsionForce& force) override;
    double execute(OpenMM::ContextImpl& context, bool includeForces, bool includeEnergy) override;
    void copyParametersToContext(OpenMM::ContextImpl& context, const DPDSoftRepulsionForce& force) override;
    std::array<double, 6> computeVirial(OpenMM::ContextImpl& context) override;

    /**
     * While deferred, execute() adds nothing: an integrator whose thermostat pair list holds
     * every pair of this force adds the force from that list instead (see pairForce), so
     * the pairs are searched once per step, not twice.
     */
    void setDeferred(bool value) { deferred = value; }
    /** Changes whenever the parameters do (for callers that cache checks on them). */
    int getParametersVersion() const { return version; }
    const TypePairTable& getTable() const { return *table; }
    bool hasExcludedPairs() const { return hasExclusions; }
    bool isPeriodic() const { return periodic; }
    /** The force on i along e = (r_i - r_j)/r of a pair at distance r (kJ/mol/nm). */
    double pairForce(int i, int j, double r) const { return pairForce(i, j, table->index(i, j), r); }
    /** The same, given the pair's table index t = getTable().index(i, j). */
    double pairForce(int i, int j, int t, double r) const {
        if (r >= table->cutoff(t) || (hasExclusions && excluded(i, j)))
            return 0;
        return SoftRepulsionPair::force(table->value(t), table->inverseCutoff(t), r);
    }

private:
    void setParameters(const DPDSoftRepulsionForce& force);
    /** Sort the particles into the search's cells at the Context's positions. */
    void search(OpenMM::ContextImpl& context);
    /** Whether the force acts on the pair of sorted slots (p, q) at squared distance r2; t is its type pair. */
    bool actsOn(int p, int q, double r2, int& t) const {
        t = table->indexOfTypes(sortedType[p], sortedType[q]);
        const std::vector<int>& sortedIndex = pairSearch->getSortedIndex();
        return r2 < table->cutoff2(t) && !(hasExclusions && excluded(sortedIndex[p], sortedIndex[q]));
    }
    bool excluded(int i, int j) const {
        const std::vector<int>& partners = exclusions[i];
        return !partners.empty() && std::binary_search(partners.begin(), partners.end(), j);
    }
    std::unique_ptr<ParallelExecutor> executor;
    std::unique_ptr<TypePairTable> table;
    std::unique_ptr<PairSearch> pairSearch;
    bool periodic = false, deferred = false, hasExclusions = false;
    int numParticles = 0, version = 0;
    std::vector<std::vector<int>> exclusions;  // sorted partners of each particle
    std::vector<std::vector<OpenMM::Vec3>> workerForces;  // by sorted slot
    std::vector<int> sortedType;                          // the type of each sorted slot
    std::vector<double> workerEnergy;
};

} // namespace DPDPlugin

#endif
