#ifndef OPENMMDPD_SWEEPDYNAMICS_H_
#define OPENMMDPD_SWEEPDYNAMICS_H_

#include "openmmdpd/LoweAndersenIntegrator.h"
#include "openmmdpd/PairDynamics.h"
#include "openmmdpd/PairSweep.h"
#include "openmmdpd/ShardlowIntegrator.h"

namespace DPDPlugin {

/**
 * Velocity Verlet with the conservative forces, split with pairwise-sequential sweeps
 * (docs/theory/shardlow.md, docs/theory/lowe-andersen.md).  The carried force is the
 * conservative force at the current positions; the pair list (and the sweep's colouring) is kept for the positions
 * it was found at.
 */
class SweepDynamics : public PairDynamics {
protected:
    SweepDynamics(const OpenMM::System& system, const DPDThermostatIntegrator& integrator, ParallelExecutor& executor);
    void stateRestored() override { pairsStep = -1; }
    void parametersChanged() override { pairsStep = -1; }
    /** At the start of a step: the carried force and the pair list at the current positions. */
    void startStep(OpenMM::ContextImpl& context, int forceGroups);
    /** v += dt/2m F ; r += dt v ; F <- FC(r), pairs at r ; v += dt/2m F. */
    void velocityVerlet(OpenMM::ContextImpl& context, int forceGroups, double dt);
    /** F <- FC(r), the pairs at r (the positions of `step`). */
    void carryForce(OpenMM::ContextImpl& context, int forceGroups, long long step);
    /** The pair list (and the sweep's colouring) at the current positions, those of `step` (-1: of no step). */
    void updatePairs(OpenMM::ContextImpl& context, long long step);
    /**
     * A new pair list, of `step`, by find(); then the sweep's colouring.  The numbers kept for
     * the old list are dropped first, so that a find that throws (a force that blew up) leaves
     * none behind for a list they do not belong to.
     */
    template <class Find>
    void findPairs(long long step, Find find) {
        normalsKept = false;
        find();
        pairSweep.prepare(thermostat);
        pairsStep = step;
    }
    /** This step's normal numbers of a stream for every pair of the current list, drawn in batches (as DrawnNormals). */
    const std::vector<double>& normals(PairRandom::Stream stream, long long step);
    /**
     * The pairs' PairNoise for a sweep with transverse friction: xi from `normals` (as the
     * sweep would take them), the noise vectors of transverseStream at `step`, drawn in batches.
     */
    const std::vector<PairNoise>& pairNoise(const std::vector<double>& normals, PairRandom::Stream transverseStream, long long step);
    /** sweep() with each pair's normal number, or its PairNoise where any pair has transverse friction. */
    template <class Rule>
    void sweepWith(std::vector<OpenMM::Vec3>& v, const Rule& rule, const std::vector<double>& normals, PairRandom::Stream transverseStream,
                   long long step, bool reverse) {
        if (thermostat.getParameters().hasTransverse())
            sweep(v, rule, pairNoise(normals, transverseStream, step), reverse);
        else
            sweep(v, rule, normals, reverse);
    }
    /**
     * Shardlow's numbers for a first sweep at `step` (RandomForce): kept from the last S2
     * step's second sweep where it drew them over the same pair list and seed, else drawn.
     */
    const std::vector<double>& firstSweepNormals(long long step);
    /**
     * S2's numbers for its second sweep, ending at step `next`: the partners of the next
     * step's first sweep's (DrawnPartnerNormals), drawn with them, which are kept.
     */
    const std::vector<double>& secondSweepNormals(long long next);
    /**
     * Apply a pair rule (PairEvaluators.h) to every pair, pair k with random[k], in the sweep
     * order or its reverse; over a list by slot, on the velocities copied into slot order and back.
     */
    template <class Rule, class Random>
    void sweep(std::vector<OpenMM::Vec3>& v, const Rule& rule, const std::vector<Random>& random, bool reverse) {
        if (!thermostat.arePairsBySlot()) {
            pairSweep.run(thermostat, v, rule, random, reverse);
            return;
        }
        const std::vector<int>& particle = thermostat.getSearch().getSortedIndex();
        slotVelocities.resize(particle.size());
        forEachParticle(particle.size(), [&](size_t k) {
            prefetchSlotParticle(v.data(), particle, k);
            slotVelocities[k] = v[particle[k]];
        });
        pairSweep.run(thermostat, slotVelocities, rule, random, reverse);
        forEachParticle(particle.size(), [&](size_t k) {
            prefetchSlotParticle(v.data(), particle, k);
            v[particle[k]] = slotVelocities[k];
        });
    }
    /**
     * body(impulse) with the pair impulse of a sweep over the current pair list at the current
     * positions, in a step of length dt (see withRecordedPairImpulse in core); over a list
     * by slot (no constraints, no virial), FreePairImpulse with the masses in slot order, or
     * EqualMassPairImpulse where all masses are equal.
     */
    template <class Body>
    void withPairImpulse(OpenMM::ContextImpl& context, double dt, Body body) {
        if (!thermostat.arePairsBySlot()) {
            withRecordedPairImpulse(constrainedImpulse, thermostat.getParameters(), *platformData(context).positions,
                                    thermostat.getPairs(), dt, thermostatVirial, impulses, body);
            return;
        }
        const std::vector<int>& particle = thermostat.getSearch().getSortedIndex();
        const std::vector<double>& invMass = thermostat.getParameters().getInverseMasses();
        if (thermostat.getParameters().hasUniformMass() && !particle.empty()) {
            body(EqualMassPairImpulse{invMass[particle[0]]});
            return;
        }
        slotInverseMasses.resize(particle.size());
        forEachParticle(particle.size(), [&](size_t k) { slotInverseMasses[k] = invMass[particle[k]]; });
        body(FreePairImpulse{slotInverseMasses});
    }
    /** Sweeps take their pairs by slot where they need no particle indices: no constraints, no virial. */
    bool wantsPairsBySlot() const override { return !constrainedImpulse.hasConstraints() && thermostatVirial == nullptr; }
    /** This step's words of a stream for every pair of the current list, drawn in batches (as DrawnBits). */
    const std::vector<r123::Philox4x32::ctr_type>& bits(PairRandom::Stream stream, long long step);

private:
    ConstrainedPairImpulse constrainedImpulse;
    PairImpulseRecord impulses;
    PairSweep pairSweep;
    long long pairsStep;
    std::vector<double> pairNormals, pairNoiseVectors;
    std::vector<PairNoise> pairNoises;
    // Where normalsKept: firstSweepNormals(nextNormalsStep) over the current list, drawn with nextNormalsSeed
    std::vector<double> nextNormals;
    bool normalsKept = false;
    long long nextNormalsStep = 0;
    uint32_t nextNormalsSeed = 0;
    std::vector<r123::Philox4x32::ctr_type> pairBits;
    std::vector<OpenMM::Vec3> slotVelocities;
    std::vector<double> slotInverseMasses;
};

/** Shardlow's S1 and S2 (ShardlowIntegrator). */
class ShardlowDynamics : public SweepDynamics {
public:
    ShardlowDynamics(const OpenMM::System& system, const ShardlowIntegrator& integrator, ParallelExecutor& executor) :
            SweepDynamics(system, integrator, executor) {}
    void step(OpenMM::ContextImpl& context, const ShardlowIntegrator& integrator);
};

/**
 * Lowe-Andersen and the exact pair Ornstein-Uhlenbeck update (LoweAndersenIntegrator), after
 * the velocity-Verlet step or between its half drifts.
 */
class LoweAndersenDynamics : public SweepDynamics {
public:
    LoweAndersenDynamics(const OpenMM::System& system, const LoweAndersenIntegrator& integrator, ParallelExecutor& executor) :
            SweepDynamics(system, integrator, executor) {}
    void step(OpenMM::ContextImpl& context, const LoweAndersenIntegrator& integrator);

private:
    /**
     * B A O A B with the velocities kept at O, as LangevinMiddleIntegrator keeps them: one
     * full kick, a half drift, O over the pairs found there, a half drift, F <- FC(r).
     */
    void middleStep(OpenMM::ContextImpl& context, const LoweAndersenIntegrator& integrator);
    /** O: the pair thermostat over dt, over the current pair list, its numbers keyed by step. */
    void applyThermostat(OpenMM::ContextImpl& context, const LoweAndersenIntegrator& integrator, long long step);
};

} // namespace DPDPlugin

#endif
