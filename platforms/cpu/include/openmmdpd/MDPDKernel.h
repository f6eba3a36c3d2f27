#ifndef OPENMMDPD_MDPDKERNEL_H_
#define OPENMMDPD_MDPDKERNEL_H_

#include "openmmdpd/DPDKernels.h"
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
 */
class MDPDKernel : public CalcMDPDForceKernel {
public:
    MDPDKernel(std::string name, const OpenMM::Platform& platform, std::unique_ptr<ParallelExecutor> executor) :
            CalcMDPDForceKernel(name, platform), executor(std::move(executor)) {}
    void initialize(const OpenMM::System& system, const MDPDForce& force) override;
    double execute(OpenMM::ContextImpl& context, bool includeForces, bool includeEnergy) override;
    void copyParametersToContext(OpenMM::ContextImpl& context, const MDPDForce& force) override;
    std::array<double, 6> computeVirial(OpenMM::ContextImpl& context) override;

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
    /** Worker w's pairs (workerPairs) and its density sums by slot (workerDensity). */
    void listPairs(int w, int workers);
    /** Worker w's pair forces by slot into workerForces; returns their energy. */
    double sumPairForces(int w, int workers, bool includeEnergy);
    /** Whether the force acts on sorted slots (p, q) at squared distance r2; t is its type pair. */
    bool actsOn(int p, int q, double r2, int& t) const;
    bool excluded(int i, int j) const {
        const std::vector<int>& partners = exclusions[i];
        return !partners.empty() && std::binary_search(partners.begin(), partners.end(), j);
    }
    /** The force on slot p along e of an accepted pair (p, q) of type pair t at distance r. */
    double pairForce(int p, int q, int t, double r) const { return parameters->pairForce(t, r, slotRepulsion[p] + slotRepulsion[q]); }
    std::unique_ptr<ParallelExecutor> executor;
    std::unique_ptr<MDPDParameters> parameters;
    std::unique_ptr<PairSearch> pairSearch;
    bool periodic = false, hasExclusions = false;
    int numParticles = 0;
    std::vector<std::vector<int>> exclusions;           // sorted partners of each particle
    std::vector<std::vector<Pair>> workerPairs;
    std::vector<std::vector<double>> workerDensity;     // by sorted slot
    std::vector<std::vector<OpenMM::Vec3>> workerForces;  // by sorted slot
    std::vector<int> sortedType;                        // the dense type of each sorted slot
    std::vector<double> slotRepulsion;                  // B rho of each sorted slot
    std::vector<double> workerEnergy;
};

} // namespace DPDPlugin

#endif
