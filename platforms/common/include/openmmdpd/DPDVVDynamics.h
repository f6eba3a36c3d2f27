#ifndef OPENMMDPD_DPDVVDYNAMICS_H_
#define OPENMMDPD_DPDVVDYNAMICS_H_

#include "openmmdpd/DPDPairCore.h"
#include "openmmdpd/DPDVVIntegrator.h"
#include "openmmdpd/ParallelExecutor.h"
#include "openmm/internal/ContextImpl.h"
#include <iosfwd>
#include <memory>

namespace DPDPlugin {

/**
 * Verlet skin of the thermostat pair list (nm).  Measured on scene soft (N = 4000,
 * rho = 4, rc = 1, dt = 0.04, CPU, one thread): a full DPD-VV step took 14.6 ms with a
 * fresh cell search every step (skin 0) and 18.2 ms with skin 0.3 (list rebuilt every
 * 2-3 steps, 2.2x more candidates to filter each step).  Hence 0: pairs are found where
 * they are evaluated.
 */
constexpr double DEFAULT_PAIR_SKIN = 0.0;

/** A step that moves a particle farther than this many thermostat cutoffs has blown up. */
constexpr double MAX_MOVE_PER_STEP = 5.0;

/**
 * The thermostat half of every pair-force DPD step: the pair list at the current
 * positions and the dissipative/random per-particle forces from it, computed over a
 * ParallelExecutor.  Integrators with a pair-force update rule (DPD-VV family, the
 * staggered scheme) call this; pairwise-sequential rules use the same pair list.
 */
class DPDThermostatForces {
public:
    DPDThermostatForces(const OpenMM::System& system, const DPDThermostatIntegrator& integrator,
                        ParallelExecutor& executor, double skin);
    const DPDPairParameters& getParameters() const { return parameters; }
    /**
     * The pair list is reused between builds, so the order in which pair forces are summed
     * depends on where it was last built: checkpoints carry that, for bit-exact continuation.
     */
    void writeSearchState(std::ostream& stream) const;
    void readSearchState(std::istream& stream);
    /** Find the pairs within their cutoffs at these positions. */
    void updatePairs(const std::vector<OpenMM::Vec3>& positions, const OpenMM::Vec3* box);
    const std::vector<PairGeometry>& getPairs() const { return pairs; }
    /** Overwrite dissipative and/or random (per `terms`) with the pair forces. */
    void compute(int terms, const std::vector<OpenMM::Vec3>& velocities, long long step, double dt,
                 std::vector<OpenMM::Vec3>& dissipative, std::vector<OpenMM::Vec3>& random);
    void setSeed(uint32_t seed) { random = PairRandom(seed); }
    uint32_t getSeed() const { return random.getSeed(); }
    const PairSearch& getSearch() const { return search; }

private:
    void buildSearch(const std::vector<OpenMM::Vec3>& positions, const OpenMM::Vec3* box);
    DPDPairParameters parameters;
    ParallelExecutor& executor;
    PairSearch search;
    PairRandom random;
    std::vector<PairGeometry> pairs;
    std::vector<std::vector<PairSearch::Pair>> workerCandidates;
    std::vector<std::vector<PairGeometry>> workerPairs;
    std::vector<std::vector<OpenMM::Vec3>> workerDissipative, workerRandom;
};

/**
 * The DPD velocity-Verlet family (algorithms.md section 1), written once over the
 * platform data that the Reference and CPU platforms share; the platforms differ only in
 * the executor (and the CPU platform's own conservative forces).
 */
class DPDVVDynamics {
public:
    DPDVVDynamics(const OpenMM::System& system, const DPDVVIntegrator& integrator, ParallelExecutor& executor, double skin);
    void step(OpenMM::ContextImpl& context, const DPDVVIntegrator& integrator);
    double computeKineticEnergy(OpenMM::ContextImpl& context) const;
    /**
     * Positions, velocities or parameters were set from outside.  Right after a checkpoint
     * was loaded, OpenMM reports the restored state this way too: then the carried force
     * is kept if the state is still the restored one when the next step starts.
     */
    void invalidateForces();
    void createCheckpoint(std::ostream& stream) const;
    void loadCheckpoint(OpenMM::ContextImpl& context, std::istream& stream);
    DPDThermostatForces& getThermostat() { return thermostat; }

private:
    /** FC <- the System's forces in the integration groups; the thermostat pairs at the same positions. */
    void computeConservativeAndPairs(OpenMM::ContextImpl& context, const DPDVVIntegrator& integrator, long long step);
    /** F <- FC + FD(v) + FR, at the current state (a start, or after outside changes). */
    void computeInitialForce(OpenMM::ContextImpl& context, const DPDVVIntegrator& integrator);
    /** Positions must be finite and no particle may have jumped (workerSums holds each worker's largest move^2). */
    void checkPositions(const std::vector<OpenMM::Vec3>& positions, long long step) const;
    void checkFinite(const std::vector<OpenMM::Vec3>& values, const char* what, long long step) const;
    double sumMV2(const std::vector<OpenMM::Vec3>& velocities) const;

    ParallelExecutor& executor;
    DPDThermostatForces thermostat;
    bool forcesValid, verifyRestoredState;
    std::vector<OpenMM::Vec3> restoredPositions, restoredVelocities;
    std::vector<OpenMM::Vec3> force, conservative, dissipative, random, predicted, velocityNoFD;
    std::vector<double> workerSums;
};

} // namespace DPDPlugin

#endif
