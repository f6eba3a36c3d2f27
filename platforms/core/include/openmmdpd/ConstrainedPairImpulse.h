#ifndef OPENMMDPD_CONSTRAINEDPAIRIMPULSE_H_
#define OPENMMDPD_CONSTRAINEDPAIRIMPULSE_H_

#include "openmmdpd/PairParameters.h"
#include "openmm/System.h"
#include "openmm/Vec3.h"
#include <Eigen/Dense>
#include <utility>
#include <vector>

namespace DPDPlugin {

/**
 * The constraint clusters of a System (particles joined by constraints): the connected
 * components of its constraint graph, each as its constraint indices in increasing order,
 * the clusters in the order of their first constraint.
 */
std::vector<std::vector<int>> findConstraintClusters(const OpenMM::System& system);

/**
 * A pair impulse in a System with constraints: J along e at i and -J at j, with the
 * constraint forces it calls up, so that the velocities stay on the constraints.  In mass
 * metric the velocity change is J d with d = M^-1 (g - C^T lambda), g the impulse's
 * direction (e at i, -e at j), C the constraint directions at the current positions and
 * lambda solving (C M^-1 C^T) lambda = C M^-1 g; the pair's relative normal velocity then
 * changes by J / mu_eff with 1/mu_eff = g.M^-1 g - (C M^-1 g).lambda.  A pair rule that
 * draws that velocity from N(0, kT/mu_eff) (Lowe) resamples one coordinate of the
 * constrained Maxwell distribution exactly, where a free-particle redraw followed by a
 * projection cools it.  Only the constraint clusters (connected by constraints) of i and j
 * take part; each cluster's matrix is factored once per sweep.  The cost is cubic in a
 * cluster's constraint count (small rigid groups: dimers, water, X-H bonds).
 */
class ConstrainedPairImpulse {
public:
    explicit ConstrainedPairImpulse(const OpenMM::System& system);
    bool hasConstraints() const { return !clusters.empty(); }
    /** Factor every cluster's constraint matrix at these positions (before each sweep). */
    void prepare(const std::vector<OpenMM::Vec3>& positions);
    /**
     * 1/mu_eff of the pair at the prepared positions, 0 where the constraints leave the pair
     * no relative motion along e; keeps the impulse's spread for the next apply() to this pair.
     */
    double inverseReducedMass(const PairGeometry& p) const;
    /** No value is common: the effective masses vary with the constraints (1 stands for any). */
    double commonInverseReducedMass() const { return 1.0; }
    /** Apply J along the pair (after inverseReducedMass for the same pair). */
    void apply(const PairGeometry& p, double impulse, std::vector<OpenMM::Vec3>& v) const;
    /**
     * An impulse across e has another effective mass for each direction: transverse friction
     * with constraints is refused before a step (DPDThermostatIntegrator::validate), and this
     * throws if reached.
     */
    void applyAcross(const PairGeometry& p, const OpenMM::Vec3& impulse, std::vector<OpenMM::Vec3>& v) const;

private:
    struct Constraint {
        int a, b;
        OpenMM::Vec3 direction;  // unit, from b to a, at the prepared positions
    };
    struct Cluster {
        std::vector<Constraint> constraints;
        Eigen::LDLT<Eigen::MatrixXd> factors;  // K = P^T L D L^T P
        Eigen::VectorXd inversePivots;         // 1/D, 0 where D marks a redundant constraint
    };
    void factor(Cluster& cluster) const;
    /** lambda = K^+ b by the factors: the redundant constraints' share of lambda is 0. */
    void solve(const Cluster& cluster, Eigen::VectorXd& x) const;
    /** Adds the cluster's constraint response to the impulse (e at i, -e at j); returns b.lambda. */
    double addClusterResponse(const Cluster& cluster, const PairGeometry& p) const;
    std::vector<double> inverseMasses;
    std::vector<int> clusterOf;  // -1 for a particle without constraints
    std::vector<Cluster> clusters;
    mutable std::vector<std::pair<int, OpenMM::Vec3>> spread;  // particle, velocity change per unit J
    mutable Eigen::VectorXd rhs, work;  // b and lambda of one cluster
};

/** The impulse on two free particles: J/m_i e at i, -J/m_j e at j. */
struct FreePairImpulse {
    const std::vector<double>& invMass;
    double inverseReducedMass(const PairGeometry& p) const { return invMass[p.i] + invMass[p.j]; }
    /** The value inverseReducedMass() gives most pairs: that of two particles like the first. */
    double commonInverseReducedMass() const { return invMass.empty() ? 1.0 : invMass[0] + invMass[0]; }
    void apply(const PairGeometry& p, double impulse, std::vector<OpenMM::Vec3>& v) const {
        v[p.i] += p.e * (impulse * invMass[p.i]);
        v[p.j] -= p.e * (impulse * invMass[p.j]);
    }
    /** An impulse J in any direction (transverse friction's, across e): J/m_i at i, -J/m_j at j. */
    void applyAcross(const PairGeometry& p, const OpenMM::Vec3& impulse, std::vector<OpenMM::Vec3>& v) const {
        v[p.i] += impulse * invMass[p.i];
        v[p.j] -= impulse * invMass[p.j];
    }
};

/**
 * FreePairImpulse where every particle has the same inverse mass: the same arithmetic,
 * without reading a mass per particle (a sweep of a large system reads them from memory).
 */
struct EqualMassPairImpulse {
    double invMass;
    double inverseReducedMass(const PairGeometry&) const { return invMass + invMass; }
    double commonInverseReducedMass() const { return invMass + invMass; }
    void apply(const PairGeometry& p, double impulse, std::vector<OpenMM::Vec3>& v) const {
        const double kick = impulse * invMass;
        v[p.i] += p.e * kick;
        v[p.j] -= p.e * kick;
    }
    void applyAcross(const PairGeometry& p, const OpenMM::Vec3& impulse, std::vector<OpenMM::Vec3>& v) const {
        v[p.i] += impulse * invMass;
        v[p.j] -= impulse * invMass;
    }
};

/**
 * body(impulse) with the pair impulse of a sweep at these positions: FreePairImpulse, or
 * `constrained` prepared at them where the System has constraints (every platform's sweeps).
 */
template <class Body>
void withPairImpulse(ConstrainedPairImpulse& constrained, const std::vector<double>& invMass,
                     const std::vector<OpenMM::Vec3>& positions, Body body) {
    if (!constrained.hasConstraints())
        body(FreePairImpulse{invMass});
    else {
        constrained.prepare(positions);
        body(static_cast<const ConstrainedPairImpulse&>(constrained));
    }
}

} // namespace DPDPlugin

#endif
