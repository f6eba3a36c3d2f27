#ifndef OPENMMDPD_MDPDKERNEL_H_
#define OPENMMDPD_MDPDKERNEL_H_

#include "openmmdpd/DPDKernels.h"
#include "openmmdpd/ExcludedPairs.h"
#include "openmmdpd/FusedPairForce.h"
#include "openmmdpd/MDPDParameters.h"
#include "openmmdpd/ParallelExecutor.h"
#include "openmmdpd/PairSearch.h"
#include <memory>
#include <vector>

namespace DPDPlugin {

/**
 * MDPDForce on the CPU platform, in two passes: each worker finds the pairs of its cells
 * with the thermostats' cell search, keeps them in a list and sums their density weights by
 * sorted slot into its own buffer; the buffers are added in worker order; then each worker
 * adds its listed pairs' forces by slot, and those buffers are added in worker order too.
 * Double precision throughout; the result does not depend on scheduling.
 *
 * Deferred (FusedPairForce), execute() sums only the densities, with a search of its own
 * over the shorter density range, and the integrator's thermostat pass adds the pair forces.
 */
class MDPDKernel : public CalcMDPDForceKernel, public FusedPairForce {
public:
    MDPDKernel(std::string name, const OpenMM::Platform& platform, std::unique_ptr<ParallelExecutor> executor) :
            CalcMDPDForceKernel(name, platform), executor(std::move(executor)) {}
    void initialize(const OpenMM::System& system, const MDPDForce& force) override;
    double execute(OpenMM::ContextImpl& context, bool includeForces, bool includeEnergy) override;
    void copyParametersToContext(OpenMM::ContextImpl& context, const MDPDForce& force) override;
    std::array<double, 6> computeVirial(OpenMM::ContextImpl& context) override;

    void setDeferred(bool value) override { deferred = value; }
    void prepare(OpenMM::ContextImpl& context) override { sumDensities(context); }
    int getParametersVersion() const override { return version; }
    const TypePairTable& getTable() const override { return parameters->getTable(); }
    bool isPeriodic() const override { return periodic; }
    bool isUniformSoftRepulsion() const override { return false; }
    const double* getParticleValues() const override { return particleRepulsion.data(); }
    void pairForces(int n, const int* first, const int* second, const int* types, const double* r, const double* valueSums,
                    double* out) const override;

private:
    void setParameters(const MDPDForce& force);
    /** A pair the force acts on, by sorted slots: d = r_p - r_q, r = |d|, t its type pair. */
    struct Pair {
        int p, q, t;
        double r;
        OpenMM::Vec3 d;
    };
    /** Sort the particles into cells, list the pairs, and sum every sorted slot's B rho (slotRepulsion) and density energy (workerEnergy). */
    void searchAndSumDensities(OpenMM::ContextImpl& context, bool includeEnergy);
    /** particleRepulsion: each particle's B rho at the Context's positions, from the pairs within rd alone. */
    void sumDensities(OpenMM::ContextImpl& context);
    /** sumDensities' pass for worker w: its cells' density sums by slot of densitySearch (workerDensity). */
    void sumWorkerDensities(int w, int workers);
    /** Worker w's pairs (workerPairs) and its density sums by slot (workerDensity). */
    void listPairs(int w, int workers);
    /** Worker w's pair forces by slot into workerForces; returns their energy. */
    double sumPairForces(int w, int workers, bool includeEnergy);
    /** Whether the force acts on sorted slots (p, q) at squared distance r2; t is its type pair. */
    bool actsOn(int p, int q, double r2, int& t) const;
    /** The force on slot p along e of an accepted pair (p, q) of type pair t at distance r. */
    double pairForce(int p, int q, int t, double r) const { return parameters->pairForce(t, r, slotRepulsion[p] + slotRepulsion[q]); }
    std::unique_ptr<ParallelExecutor> executor;
    std::unique_ptr<MDPDParameters> parameters;
    std::unique_ptr<PairSearch> pairSearch;
    std::unique_ptr<PairSearch> densitySearch;          // over rd only: sumDensities'
    bool periodic = false, deferred = false;
    int numParticles = 0, version = 0;
    ExcludedPairs excludedPairs;
    std::vector<std::vector<Pair>> workerPairs;
    std::vector<std::vector<double>> workerDensity;     // by sorted slot
    std::vector<std::vector<OpenMM::Vec3>> workerForces;  // by sorted slot
    std::vector<int> sortedType;                        // the dense type of each sorted slot
    std::vector<double> slotRepulsion;                  // B rho of each sorted slot
    std::vector<double> particleRepulsion;              // B rho of each particle (sumDensities')
    std::vector<double> workerEnergy;
};

} // namespace DPDPlugin

#endif
