#ifndef OPENMMDPD_PAIRDYNAMICS_H_
#define OPENMMDPD_PAIRDYNAMICS_H_

#include "openmmdpd/CheckpointIO.h"
#include "openmmdpd/ConstrainedMotion.h"
#include "openmmdpd/DPDThermostatForces.h"
#include "openmmdpd/FusedPairForce.h"
#include "openmmdpd/LeesEdwardsBoundary.h"
#include "openmmdpd/PressureTensor.h"
#include "openmmdpd/ReferencePositionStrain.h"
#include "openmmdpd/StepState.h"
#include "openmm/internal/ContextImpl.h"
#include "ReferencePlatform.h"
#include <algorithm>
#include <iosfwd>
#include <string>

namespace DPDPlugin {

/**
 * What every DPD update rule shares, written once over the platform data that the
 * Reference and CPU platforms have in common: the thermostat pairs and their random
 * numbers, the force carried from one step to the next (and its invalidation, also across
 * checkpoints), conservative forces from the System, blow-up checks and the kinetic energy.
 * A subclass writes its update rule in a step(context, integrator) of its integrator class.
 */
class PairDynamics {
public:
    PairDynamics(const OpenMM::System& system, const DPDThermostatIntegrator& integrator, ParallelExecutor& executor,
                 int cellMultiple);
    virtual ~PairDynamics() {}
    double computeKineticEnergy(OpenMM::ContextImpl& context) const;
    /**
     * Positions, velocities or parameters were set from outside.  Right after a checkpoint
     * was loaded, OpenMM reports the restored state this way too: then the carried force
     * is kept if the state is still the restored one when the next step starts.
     */
    void invalidateForces() { carried.invalidate(); }
    /** The integrator's thermostat parameters changed on a live Context: use them from now on. */
    void updateParameters(const OpenMM::System& system, const DPDThermostatIntegrator& integrator);
    /**
     * The steps from now on add the virial of the thermostat's pair forces (or of its sweeps'
     * pair impulses over dt) to `sink`, if not null (PressureTensorSampler).
     */
    void recordThermostatVirial(SymmetricTensor* sink) { thermostatVirial = sink; }
    /** How the pressure tensor strains the positions. */
    PositionStrain& positionStrain() { return strain; }
    /** The pair random numbers come from this seed from now on. */
    void setSeed(uint32_t seed) { thermostat.setSeed(seed); }
    void createCheckpoint(std::ostream& stream) const;
    /** Reads and checks the whole payload, then replaces the carried state with it. */
    void loadCheckpoint(OpenMM::ContextImpl& context, CheckpointReader& reader);
    /** Drops everything carried: the next step starts from the Context's state as a new Context would. */
    void resetState();

protected:
    /** Whether computeConservativeAndPairs finds the pairs by slot (DPDThermostatForces::arePairsBySlot). */
    virtual bool wantsPairsBySlot() const { return false; }
    /** Called after a checkpoint was loaded or refused (state kept beyond the carried force is stale). */
    virtual void stateRestored() {}
    /** Called after the thermostat parameters changed (state derived from them is stale). */
    virtual void parametersChanged() {}
    /**
     * A subclass that carries more than `force` from one step to the next writes it here
     * (after the shared part of the checkpoint), reads and checks it without using it in
     * loadExtraState(), takes it into use in commitExtraState() and drops it in
     * resetExtraState().
     */
    virtual void saveExtraState(std::ostream& stream) const {}
    virtual void loadExtraState(CheckpointReader& reader) {}
    virtual void commitExtraState() {}
    virtual void resetExtraState() {}
    /** Call at the start of a step: whether `force` still holds for the current state. */
    bool carriedForceValid(const std::vector<OpenMM::Vec3>& positions, const std::vector<OpenMM::Vec3>& velocities) {
        return carried.isValid(positions, velocities);
    }
    void setCarriedForceValid() { carried.setValid(); }
    /**
     * conservative <- the integration force groups' forces; the thermostat pairs at the same
     * positions.  A DPDSoftRepulsionForce or MDPDForce whose pairs all lie within the thermostat's is
     * evaluated from the thermostat pair list (one pair search per step instead of two).
     */
    void computeConservativeAndPairs(OpenMM::ContextImpl& context, int forceGroups, long long step);
    /**
     * out <- the integration force groups' forces + FD(velocities) + FR at the current
     * positions, in one pass over the pairs (prepareSlotPasses, DPDThermostatForces::sumBySlot): for
     * update rules that need only that sum.  The pair list is not updated.
     */
    void computeForceInOnePass(OpenMM::ContextImpl& context, int forceGroups, const std::vector<OpenMM::Vec3>& velocities,
                               long long step, double dt, std::vector<OpenMM::Vec3>& out);
    /**
     * The integration force groups' forces and the thermostat's search at the current
     * positions (of `step`), for passes over the pairs with thermostat.sumBySlot(); returns
     * the base that one of those passes is to add (null: none), with the fused force `fused`
     * (null: none) that the pairs carry.
     */
    const std::vector<OpenMM::Vec3>* prepareSlotPasses(OpenMM::ContextImpl& context, int forceGroups, long long step,
                                                       const FusedPairForce*& fused);
    /**
     * conservative <- the forces of these groups at the current positions (the Context's by
     * default; there a fused force that can be is left to the thermostat pair list, see
     * computeConservativeAndPairs).
     */
    virtual void computeConservative(OpenMM::ContextImpl& context, int forceGroups);
    /**
     * The drift of a step of length dt ending at `step`: r[i] += displacement(i) for every
     * particle, in parallel, the blow-up checks (non-finite, or a jump of more than
     * MAX_MOVE_PER_STEP cutoffs), then the constraints and virtual sites
     * (ConstrainedMotion::finishDrift, which also corrects the velocities and `alsoCorrect`),
     * and under shear the sliding boundary (LeesEdwardsBoundary::slide).
     */
    template <class Displacement>
    void movePositions(OpenMM::ContextImpl& context, long long step, double dt, Displacement displacement,
                       std::vector<OpenMM::Vec3>* alsoCorrect = nullptr);
    /** After a velocity change: remove the velocity components along the constraints. */
    void constrainVelocities(OpenMM::ContextImpl& context) { motion.constrainVelocities(context); }
    /** body(i) for i in [0, n), in parallel when n is large enough to pay for it. */
    template <class Body>
    void forEachParticle(size_t n, Body body) {
        executor.forEach(n, body);
    }
    /**
     * r[i] += displacement(i) for the listed particles only (serially: meant for a small
     * subset, e.g. a staggered scheme's polymer), then the same blow-up checks on them.
     */
    template <class Displacement>
    void moveParticles(const std::vector<int>& particles, std::vector<OpenMM::Vec3>& r, long long step, Displacement displacement);
    /** Whether pass(begin, end) holds for every worker's range of [0, n): in parallel when n is large enough to pay for it. */
    template <class Pass>
    bool passesEverywhere(size_t n, Pass pass) const {
        std::vector<char> passed(executor.getNumWorkers(), 1);
        executor.forEachRange(n, [&](int w, size_t begin, size_t end) { passed[w] = pass(begin, end); });
        return std::all_of(passed.begin(), passed.end(), [](char p) { return p != 0; });
    }
    /** DPDPlugin::checkFinite, tested in parallel (the serial check then names the first value that fails). */
    void checkFinite(const std::vector<OpenMM::Vec3>& values, const char* what, long long step) const {
        if (!passesEverywhere(values.size(), [&](size_t begin, size_t end) { return allFinite(values, begin, end); }))
            DPDPlugin::checkFinite(values, what, step, name);
    }
    /** The same check on values[particles[k]] (or values[k] with indexedByParticle false), naming particles[k]. */
    void checkFinite(const std::vector<OpenMM::Vec3>& values, const std::vector<int>& particles, bool indexedByParticle,
                     const char* what, long long step) const;
    /**
     * End a step: the velocities must be finite (and under the instability threshold, see
     * checkVelocities); the Context's step count and time advance.
     */
    void finishStep(OpenMM::ReferencePlatform::PlatformData& data, double dt) const;
    /** sum m v^2 over these velocities, with these masses (in the same order). */
    double sumMV2(const std::vector<OpenMM::Vec3>& velocities, const std::vector<double>& mass) const;
    static OpenMM::ReferencePlatform::PlatformData& platformData(OpenMM::ContextImpl& context) {
        return *static_cast<OpenMM::ReferencePlatform::PlatformData*>(context.getPlatformData());
    }

    std::string name;
    ParallelExecutor& executor;
    DPDThermostatForces thermostat;
    CarriedForce carried;
    SymmetricTensor* thermostatVirial = nullptr;  // see recordThermostatVirial
    ReferencePositionStrain strain;
    std::vector<OpenMM::Vec3>& force;  // carried.force
    std::vector<OpenMM::Vec3> conservative;
    mutable std::vector<double> workerSums;
    ConstrainedMotion motion;
    LeesEdwardsBoundary shear;

    /**
     * The DPDSoftRepulsionForce or MDPDForce of these groups that the thermostat pairs can
     * carry (the one such force, every particle in the thermostat, no force cutoff beyond
     * the thermostat cutoff of the same pair), or null.
     */
    FusedPairForce* pairForceToFuse(OpenMM::ContextImpl& context, int forceGroups);
    /**
     * For a computeConservative() that evaluates the other forces elsewhere: this step adds
     * `fused` (from pairForceToFuse) from the thermostat pairs, prepared at the Context's positions.
     */
    void addForceFromPairs(OpenMM::ContextImpl& context, FusedPairForce* fused) {
        fused->prepare(context);
        forceFromPairs = fused;
    }

private:
    void checkMoves(long long step) const;
    FusedPairForce* fusedForce = nullptr;
    FusedPairForce* forceFromPairs = nullptr;  // deferred by this step's computeConservative
    int fusedForceGroups = 0, fusedVersion = -1;
    bool fusedIsAlone = false;        // the fused force is the only force in fusedForceGroups
    bool conservativeIsZero = false;  // this step's computeConservative had nothing to add (and left `conservative` unset)
    std::vector<OpenMM::Vec3> fusedForceSum;
};

template <class Displacement>
void PairDynamics::movePositions(OpenMM::ContextImpl& context, long long step, double dt, Displacement displacement,
                                 std::vector<OpenMM::Vec3>* alsoCorrect) {
    std::vector<OpenMM::Vec3>& r = *platformData(context).positions;
    motion.startDrift(r);
    auto move = [&](size_t begin, size_t end) {
        double maxMove2 = 0;
        for (size_t i = begin; i < end; i++) {
            const OpenMM::Vec3 move = displacement(i);
            r[i] += move;
            maxMove2 = std::max(maxMove2, move.dot(move));
        }
        return maxMove2;
    };
    std::fill(workerSums.begin(), workerSums.end(), 0.0);
    executor.forEachRange(r.size(), [&](int w, size_t begin, size_t end) { workerSums[w] = move(begin, end); });
    checkFinite(r, "position", step);
    checkMoves(step);
    motion.finishDrift(context, dt, alsoCorrect);
    shear.slide(context, thermostat.getParameters().getShearRate(), dt, r, *platformData(context).velocities, alsoCorrect);
}

template <class Displacement>
void PairDynamics::moveParticles(const std::vector<int>& particles, std::vector<OpenMM::Vec3>& r, long long step,
                                 Displacement displacement) {
    double maxMove2 = 0;
    for (size_t k = 0; k < particles.size(); k++) {
        const OpenMM::Vec3 move = displacement(k);
        r[particles[k]] += move;
        maxMove2 = std::max(maxMove2, move.dot(move));
    }
    std::fill(workerSums.begin(), workerSums.end(), 0.0);
    workerSums[0] = maxMove2;
    checkFinite(r, particles, true, "position", step);
    checkMoves(step);
}

} // namespace DPDPlugin

#endif
