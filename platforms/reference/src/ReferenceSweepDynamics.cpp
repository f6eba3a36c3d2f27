#include "openmmdpd/ReferenceSweepDynamics.h"

using namespace DPDPlugin;
using OpenMM::Vec3;

namespace {

/**
 * The pairwise-sequential sweep: the rule updates each pair's velocities in place, in the
 * given order, so every pair sees the velocities the pairs before it left; draw(p) gives
 * each pair its random input.
 */
template <class Rule, class Draw>
void sweep(const std::vector<PairGeometry>& pairs, const Rule& rule, const Draw& draw, std::vector<Vec3>& v) {
    for (const PairGeometry& p : pairs)
        rule(p, draw(p), v);
}

/** The same sweep in exactly the opposite order (S2's second half, which makes S2 symmetric). */
template <class Rule, class Draw>
void sweepInReverse(const std::vector<PairGeometry>& pairs, const Rule& rule, const Draw& draw, std::vector<Vec3>& v) {
    for (size_t k = pairs.size(); k-- > 0;)
        rule(pairs[k], draw(pairs[k]), v);
}

/** The numbers a sweep's pairs take: a pair's normal number of a stream and step (its partner's, `partner`). */
struct SweepNumbers {
    const PairRandom& random;
    PairRandom::Stream stream;
    long long step;
    bool partner;
    PairRandom::Stream transverseStream;  // with transverse friction: each pair's PairNoise, its vector from this stream
};

/** The sweep (or, reverse, its reverse) with the pairs' numbers: PairNoise where any pair has transverse friction. */
template <class Rule>
void sweepWith(const std::vector<PairGeometry>& pairs, const Rule& rule, const SweepNumbers& n, bool transverse, bool reverse,
               std::vector<Vec3>& v) {
    const auto run = [&](const auto& draw) { reverse ? sweepInReverse(pairs, rule, draw, v) : sweep(pairs, rule, draw, v); };
    if (transverse)
        run(DrawnPairNoise{n.random, n.stream, n.transverseStream, n.step, n.partner});
    else if (n.partner)
        run(DrawnPartnerNormals{n.random, n.stream, n.step});
    else
        run(DrawnNormals{n.random, n.stream, n.step});
}

} // namespace

void ReferenceSweepDynamics::ensureCarriedForce(OpenMM::ContextImpl& context, int forceGroups) {
    // Invalid after the positions, velocities or parameters were set from outside.
    if (!carried.isValid(*data(context).positions, *data(context).velocities)) {
        carried.force = conservativeForce(context, forceGroups, data(context).stepCount);
        carried.setValid();
    }
}

void ReferenceSweepDynamics::velocityVerlet(OpenMM::ContextImpl& context, int forceGroups, double dt) {
    std::vector<Vec3>& r = *data(context).positions;
    std::vector<Vec3>& v = *data(context).velocities;
    std::vector<Vec3>& F = carried.force;
    const std::vector<double>& invMass = parameters.getInverseMasses();
    const long long next = data(context).stepCount + 1;
    const size_t n = r.size();
    // v += dt/2m F ; r += dt v
    std::vector<Vec3> move(n);
    for (size_t i = 0; i < n; i++) {
        v[i] += F[i] * (0.5 * dt * invMass[i]);
        move[i] = v[i] * dt;
    }
    movePositions(context, move, next, dt);
    // F <- FC(r) at the new positions (carried into the next step)
    F = conservativeForce(context, forceGroups, next);
    // v += dt/2m F
    for (size_t i = 0; i < n; i++)
        v[i] += F[i] * (0.5 * dt * invMass[i]);
    constrainVelocities(context);
}

void ReferenceShardlowDynamics::step(OpenMM::ContextImpl& context, const ShardlowIntegrator& integrator) {
    std::vector<Vec3>& v = *data(context).velocities;
    const double dt = integrator.getStepSize();
    const int forceGroups = integrator.getIntegrationForceGroups();
    // Every random number of the step is keyed by the step it starts from (but S2's second sweep's).
    const long long current = data(context).stepCount;
    ensureCarriedForce(context, forceGroups);
    const bool secondOrder = (integrator.getOrder() == 2);
    const double h = secondOrder ? 0.5 * dt : dt;
    // S1: sweep (dt) ; VV.  S2: sweep (dt/2) ; VV ; sweep (dt/2) in the reverse order, over
    // the pairs at the new positions, with the partners of the numbers the next step's first
    // sweep takes over the same pairs (independent of them and of this step's).
    // Transverse friction draws its noise vectors from streams of their own, keyed as the numbers along e.
    const bool transverse = parameters.hasTransverse();
    const std::vector<PairGeometry> pairs = findPairs(context);
    withPairImpulse(context, pairs, dt, [&](const auto& impulse) {
        sweepWith(pairs, ShardlowPairUpdate<decltype(impulse)>{h, impulse},
                  SweepNumbers{random, PairRandom::RandomForce, current, false, PairRandom::TransverseNoise}, transverse, false, v);
    });
    constrainVelocities(context);
    velocityVerlet(context, forceGroups, dt);
    if (secondOrder) {
        const std::vector<PairGeometry> newPairs = findPairs(context);
        withPairImpulse(context, newPairs, dt, [&](const auto& impulse) {
            sweepWith(newPairs, ShardlowPairUpdate<decltype(impulse)>{h, impulse},
                      SweepNumbers{random, PairRandom::RandomForce, current + 1, true, PairRandom::TransverseSecondSweep}, transverse,
                      true, v);
        });
        constrainVelocities(context);
    }
    finishStep(context, dt);
}

void ReferenceLoweAndersenDynamics::step(OpenMM::ContextImpl& context, const LoweAndersenIntegrator& integrator) {
    const double dt = integrator.getStepSize();
    const int forceGroups = integrator.getIntegrationForceGroups();
    ensureCarriedForce(context, forceGroups);
    if (integrator.getSplitting() == LoweAndersenIntegrator::Middle)
        middleStep(context, integrator);
    else {
        // B A A B O: VV ; the pair thermostat over dt, over the pairs at the new positions.
        const long long current = data(context).stepCount;
        velocityVerlet(context, forceGroups, dt);
        applyThermostat(context, integrator, current);
    }
    finishStep(context, dt);
}

void ReferenceLoweAndersenDynamics::middleStep(OpenMM::ContextImpl& context, const LoweAndersenIntegrator& integrator) {
    std::vector<Vec3>& r = *data(context).positions;
    std::vector<Vec3>& v = *data(context).velocities;
    std::vector<Vec3>& F = carried.force;
    const std::vector<double>& invMass = parameters.getInverseMasses();
    const double dt = integrator.getStepSize();
    const long long current = data(context).stepCount, next = current + 1;
    const size_t n = r.size();
    // B B (the last step's closing half kick and this step's opening one) A: v += dt/m F ; r += dt/2 v
    std::vector<Vec3> move(n);
    for (size_t i = 0; i < n; i++) {
        v[i] += F[i] * (dt * invMass[i]);
        move[i] = v[i] * (0.5 * dt);
    }
    movePositions(context, move, next, 0.5 * dt);
    // O over dt, over the pairs at the mid-step positions
    applyThermostat(context, integrator, current);
    // A: r += dt/2 v ; F <- FC(r)
    for (size_t i = 0; i < n; i++)
        move[i] = v[i] * (0.5 * dt);
    movePositions(context, move, next, 0.5 * dt);
    F = conservativeForce(context, integrator.getIntegrationForceGroups(), next);
}

void ReferenceLoweAndersenDynamics::applyThermostat(OpenMM::ContextImpl& context, const LoweAndersenIntegrator& integrator, long long step) {
    std::vector<Vec3>& v = *data(context).velocities;
    const double dt = integrator.getStepSize(), kT = parameters.getKT();
    const std::vector<PairGeometry> pairs = findPairs(context);
    withPairImpulse(context, pairs, dt, [&](const auto& impulse) {
        using Impulse = decltype(impulse);
        if (integrator.getMethod() == LoweAndersenIntegrator::Lowe)
            sweep(pairs, LowePairUpdate<Impulse>{dt, kT, impulse}, DrawnBits{random, PairRandom::PairThermalisation, step}, v);
        else
            sweepWith(pairs, PairOrnsteinUhlenbeckUpdate<Impulse>{dt, kT, impulse},
                      SweepNumbers{random, PairRandom::PairThermalisation, step, false, PairRandom::TransverseNoise},
                      parameters.hasTransverse(), false, v);
    });
    constrainVelocities(context);
}
