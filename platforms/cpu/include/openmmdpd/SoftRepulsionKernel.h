#ifndef OPENMMDPD_SOFTREPULSIONKERNEL_H_
#define OPENMMDPD_SOFTREPULSIONKERNEL_H_

#include "openmmdpd/DPDKernels.h"
#include "openmmdpd/ExcludedPairs.h"
#include "openmmdpd/DPDPairCore.h"
#include "openmmdpd/FusedPairForce.h"
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
class SoftRepulsionKernel : public CalcDPDSoftRepulsionForceKernel, public FusedPairForce {
public:
    SoftRepulsionKernel(std::string name, const OpenMM::Platform& platform, std::unique_ptr<ParallelExecutor> executor) :
            CalcDPDSoftRepulsionForceKernel(name, platform), executor(std::move(executor)) {}
    void initialize(const OpenMM::System& system, const DPDSoftRepulsionForce& force) override;
    double execute(OpenMM::ContextImpl& context, bool includeForces, bool includeEnergy) override;
    void copyParametersToContext(OpenMM::ContextImpl& context, const DPDSoftRepulsionForce& force) override;
    std::array<double, 6> computeVirial(OpenMM::ContextImpl& context) override;

    /** While deferred, execute() adds nothing: an integrator's thermostat pass adds the force (FusedPairForce). */
    void setDeferred(bool value) override { deferred = value; }
    void prepare(OpenMM::ContextImpl&) override {}
    int getParametersVersion() const override { return version; }
    const TypePairTable& getTable() const override { return *table; }
    bool isPeriodic() const override { return periodic; }
    bool isUniformSoftRepulsion() const override { return table->getNumTypes() == 1 && excludedPairs.empty(); }
    const double* getParticleValues() const override { return nullptr; }
    void pairForces(int n, const int* first, const int* second, const int* types, const double* r, const double*,
                    double* out) const override {
        for (int k = 0; k < n; k++)
            out[k] = pairForce(first[k], second[k], types[k], r[k]);
    }
    /** The force on i along e = (r_i - r_j)/r of a pair at distance r of table index t (kJ/mol/nm). */
    double pairForce(int i, int j, int t, double r) const {
        if (r >= table->cutoff(t) || excludedPairs.contains(i, j))
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
        return r2 < table->cutoff2(t) && !excludedPairs.contains(sortedIndex[p], sortedIndex[q]);
    }
    std::unique_ptr<ParallelExecutor> executor;
    std::unique_ptr<TypePairTable> table;
    std::unique_ptr<PairSearch> pairSearch;
    bool periodic = false, deferred = false;
    int numParticles = 0, version = 0;
    ExcludedPairs excludedPairs;
    std::vector<std::vector<OpenMM::Vec3>> workerForces;  // by sorted slot
    std::vector<int> sortedType;                          // the type of each sorted slot
    std::vector<double> workerEnergy;
};

} // namespace DPDPlugin

#endif
