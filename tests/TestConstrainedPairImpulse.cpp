/*
 * ConstrainedPairImpulse against closed forms: the effective reduced mass of a pair whose
 * particles belong to rigid groups, and an impulse that leaves every constraint's relative
 * velocity at zero, conserves momentum and changes the pair's relative normal velocity by
 * J / mu_eff; so that Shardlow's halves add up to one kick with it as with free particles.
 */
#include "openmmdpd/ConstrainedPairImpulse.h"
#include "openmmdpd/PairEvaluators.h"
#include "openmm/System.h"
#include <gtest/gtest.h>
#include <cmath>

using namespace DPDPlugin;
using OpenMM::System;
using OpenMM::Vec3;

namespace {

PairGeometry pair(const std::vector<Vec3>& r, int i, int j) {
    const Vec3 d = r[i] - r[j];
    return PairGeometry{i, j, d / std::sqrt(d.dot(d)), 0, 0, 0, 0};
}

/** Max over the constraints of |(v_a - v_b) . (r_a - r_b)| / |r_a - r_b|. */
double constraintVelocity(const System& system, const std::vector<Vec3>& r, const std::vector<Vec3>& v) {
    double worst = 0;
    for (int k = 0; k < system.getNumConstraints(); k++) {
        int a, b;
        double d;
        system.getConstraintParameters(k, a, b, d);
        const Vec3 rab = r[a] - r[b];
        worst = std::max(worst, std::fabs((v[a] - v[b]).dot(rab)) / std::sqrt(rab.dot(rab)));
    }
    return worst;
}

Vec3 momentum(const System& system, const std::vector<Vec3>& v) {
    Vec3 p;
    for (int i = 0; i < system.getNumParticles(); i++)
        p += v[i] * system.getParticleMass(i);
    return p;
}

/**
 * A dimer (0, 1) of masses 1 and 3 along x, a rigid triangle (2, 3, 4) of masses 16, 1, 1,
 * a free particle 5 of mass 2, a constraint listed twice (redundant) in the triangle, and a
 * bent chain (6, 7, 8) of masses 2, 1, 4 with two bonds and no angle constraint, whose ends
 * can move relative to each other.
 */
struct Groups {
    System system;
    std::vector<Vec3> r = {Vec3(0, 0, 0), Vec3(0.5, 0, 0), Vec3(2, 0, 0), Vec3(2.1, 0.09, 0), Vec3(1.95, 0.09, 0.05), Vec3(0.3, 0.6, 0.2),
                          Vec3(1, 1, 1), Vec3(1.4, 1, 1), Vec3(1.6, 1.3, 1.1)};
    Groups() {
        for (double m : {1.0, 3.0, 16.0, 1.0, 1.0, 2.0, 2.0, 1.0, 4.0})
            system.addParticle(m);
        system.addConstraint(0, 1, 0.5);
        system.addConstraint(2, 3, 0.1);
        system.addConstraint(2, 4, 0.1);
        system.addConstraint(3, 4, 0.16);
        system.addConstraint(4, 2, 0.1);
        system.addConstraint(6, 7, 0.4);
        system.addConstraint(7, 8, std::sqrt(0.14));
    }
};

TEST(ConstrainedPairImpulse, DimerAndFreeParticleHaveTheClosedFormReducedMass) {
    Groups g;
    ConstrainedPairImpulse impulse(g.system);
    impulse.prepare(g.r);
    const PairGeometry p = pair(g.r, 0, 5);
    // Along the bond (x) particle 0 moves with the whole dimer (mass 4), across it alone (mass 1).
    const double along = p.e[0];
    const double expected = 1 / 2.0 + along * along / 4.0 + (1 - along * along) / 1.0;
    EXPECT_NEAR(impulse.inverseReducedMass(p), expected, 1e-14);
}

TEST(ConstrainedPairImpulse, PairWithinARigidGroupHasNoRelativeMotion) {
    Groups g;
    ConstrainedPairImpulse impulse(g.system);
    impulse.prepare(g.r);
    EXPECT_EQ(impulse.inverseReducedMass(pair(g.r, 0, 1)), 0.0);
    EXPECT_EQ(impulse.inverseReducedMass(pair(g.r, 3, 4)), 0.0);
    EXPECT_EQ(impulse.inverseReducedMass(pair(g.r, 2, 4)), 0.0);
}

TEST(ConstrainedPairImpulse, ImpulseKeepsTheConstraintsAndMomentumAndMovesThePairByJOverMu) {
    Groups g;
    ConstrainedPairImpulse impulse(g.system);
    impulse.prepare(g.r);
    for (const std::pair<int, int>& ij : std::vector<std::pair<int, int>>{{0, 3}, {4, 1}, {5, 2}, {5, 0}, {6, 8}}) {
        const PairGeometry p = pair(g.r, ij.first, ij.second);
        std::vector<Vec3> v(g.r.size());  // at rest: every constraint velocity holds
        const double inverse = impulse.inverseReducedMass(p);
        ASSERT_GT(inverse, 0.0);
        impulse.apply(p, 0.7, v);
        EXPECT_LT(constraintVelocity(g.system, g.r, v), 1e-14) << ij.first << "-" << ij.second;
        const Vec3 dp = momentum(g.system, v);
        EXPECT_LT(std::sqrt(dp.dot(dp)), 1e-14);
        EXPECT_NEAR(p.e.dot(v[p.i] - v[p.j]), 0.7 * inverse, 1e-14);
        // The constraints only ever take motion away: mu_eff >= the free reduced mass.
        EXPECT_LE(inverse, 1 / g.system.getParticleMass(p.i) + 1 / g.system.getParticleMass(p.j) + 1e-15);
    }
}

// Its pair's u changes by J / mu_eff, so ShardlowForm's algebra holds with mu_eff for mu:
// the CPU platform's one kick gives the two halves' velocities to rounding here too.
TEST(ConstrainedPairImpulse, ShardlowOneKickIsTheTwoHalvesToRounding) {
    Groups g;
    ConstrainedPairImpulse impulse(g.system);
    impulse.prepare(g.r);
    std::vector<Vec3> v0(g.r.size());
    impulse.inverseReducedMass(pair(g.r, 5, 3));  // a start in motion that keeps the constraints
    impulse.apply(pair(g.r, 5, 3), 1.3, v0);
    impulse.inverseReducedMass(pair(g.r, 5, 8));
    impulse.apply(pair(g.r, 5, 8), -0.9, v0);
    // (6, 8): both in one cluster, not held rigid by it
    for (const std::pair<int, int>& ij : std::vector<std::pair<int, int>>{{0, 3}, {4, 1}, {5, 2}, {5, 0}, {6, 8}}) {
        for (double h : {0.01, 0.2}) {
            PairGeometry p = pair(g.r, ij.first, ij.second);
            p.gammaWD = 4.5 * 0.3 * 0.3;
            p.sigmaWR = 3.0 * 0.3;
            std::vector<Vec3> halves = v0, oneKick = v0;
            ShardlowPairUpdate<const ConstrainedPairImpulse&, ShardlowForm::TwoHalves>(h, impulse)(p, -0.8, halves);
            ShardlowPairUpdate<const ConstrainedPairImpulse&, ShardlowForm::OneKick>(h, impulse)(p, -0.8, oneKick);
            for (size_t k = 0; k < v0.size(); k++) {
                const Vec3 d = halves[k] - oneKick[k];
                ASSERT_LT(std::sqrt(d.dot(d)), 1e-14) << ij.first << "-" << ij.second << " h " << h << " particle " << k;
            }
            const Vec3 moved = halves[p.i] - v0[p.i];
            ASSERT_GT(std::sqrt(moved.dot(moved)), 1e-3);  // the pair was kicked
        }
    }
}

// A rod of three collinear particles held by all three distances: K has rank 2 (a redundancy
// that is not a repeated constraint).  Along the rod particle 0 moves with the whole rod, across
// it alone (the constraints are parallel), as for the dimer.
TEST(ConstrainedPairImpulse, CollinearRodWithARedundantConstraintHasTheClosedFormReducedMass) {
    System system;
    for (double m : {1.0, 2.0, 4.0, 3.0})
        system.addParticle(m);
    const Vec3 axis = Vec3(0.267, 0.534, 0.802) / std::sqrt(0.267 * 0.267 + 0.534 * 0.534 + 0.802 * 0.802);
    const std::vector<Vec3> r = {Vec3(0.1, 0.2, 0.3), Vec3(0.1, 0.2, 0.3) + axis * 0.37, Vec3(0.1, 0.2, 0.3) + axis * 1.13,
                                 Vec3(0.9, -0.4, 0.5)};
    system.addConstraint(0, 1, 0.37);
    system.addConstraint(1, 2, 0.76);
    system.addConstraint(0, 2, 1.13);
    ConstrainedPairImpulse impulse(system);
    impulse.prepare(r);
    const PairGeometry p = pair(r, 0, 3);
    const double along = p.e.dot(axis);
    const double expected = 1 / 3.0 + along * along / 7.0 + (1 - along * along) / 1.0;
    EXPECT_NEAR(impulse.inverseReducedMass(p), expected, 1e-12);
    std::vector<Vec3> v(r.size());
    impulse.apply(p, 0.7, v);
    EXPECT_LT(constraintVelocity(system, r, v), 1e-12);
}

TEST(ConstrainedPairImpulse, FreeParticlesHaveTheirOwnReducedMass) {
    System system;
    system.addParticle(2.0);
    system.addParticle(6.0);
    ConstrainedPairImpulse impulse(system);
    EXPECT_FALSE(impulse.hasConstraints());
    const std::vector<Vec3> r = {Vec3(), Vec3(0.3, 0.4, 0)};
    impulse.prepare(r);
    EXPECT_DOUBLE_EQ(impulse.inverseReducedMass(pair(r, 0, 1)), 1 / 2.0 + 1 / 6.0);
}

} // namespace
