#include "openmmdpd/ConstrainedPairImpulse.h"
#include "openmm/OpenMMException.h"
#include <cmath>
#include <numeric>
#include <string>

using namespace DPDPlugin;
using OpenMM::Vec3;

namespace {

int findRoot(std::vector<int>& parent, int i) {
    while (parent[i] != i)
        i = parent[i] = parent[parent[i]];
    return i;
}

} // namespace

std::vector<std::vector<int>> DPDPlugin::findConstraintClusters(const OpenMM::System& system) {
    const int n = system.getNumParticles();
    std::vector<int> parent(n);
    std::iota(parent.begin(), parent.end(), 0);
    for (int k = 0; k < system.getNumConstraints(); k++) {
        int a, b;
        double distance;
        system.getConstraintParameters(k, a, b, distance);
        parent[findRoot(parent, a)] = findRoot(parent, b);
    }
    std::vector<int> clusterOfRoot(n, -1);
    std::vector<std::vector<int>> clusters;
    for (int k = 0; k < system.getNumConstraints(); k++) {
        int a, b;
        double distance;
        system.getConstraintParameters(k, a, b, distance);
        int& cluster = clusterOfRoot[findRoot(parent, a)];
        if (cluster < 0) {
            cluster = (int) clusters.size();
            clusters.emplace_back();
        }
        clusters[cluster].push_back(k);
    }
    return clusters;
}

ConstrainedPairImpulse::ConstrainedPairImpulse(const OpenMM::System& system) :
        inverseMasses(system.getNumParticles()), clusterOf(system.getNumParticles(), -1) {
    for (int i = 0; i < system.getNumParticles(); i++) {
        const double mass = system.getParticleMass(i);
        inverseMasses[i] = (mass > 0 ? 1 / mass : 0);
    }
    for (const std::vector<int>& members : findConstraintClusters(system)) {
        clusters.emplace_back();
        for (int k : members) {
            int a, b;
            double distance;
            system.getConstraintParameters(k, a, b, distance);
            clusters.back().constraints.push_back(Constraint{a, b, Vec3()});
            clusterOf[a] = clusterOf[b] = (int) clusters.size() - 1;
        }
    }
}

void ConstrainedPairImpulse::prepare(const std::vector<Vec3>& positions) {
    for (Cluster& cluster : clusters) {
        for (Constraint& c : cluster.constraints) {
            const Vec3 d = positions[c.a] - positions[c.b];
            c.direction = d / std::sqrt(d.dot(d));
        }
        factor(cluster);
    }
}

void ConstrainedPairImpulse::factor(Cluster& cluster) const {
    // K = C M^-1 C^T, C's row k being +c_k at a_k and -c_k at b_k.
    const std::vector<Constraint>& c = cluster.constraints;
    const Eigen::Index n = (Eigen::Index) c.size();
    Eigen::MatrixXd K(n, n);
    for (Eigen::Index k = 0; k < n; k++)
        for (Eigen::Index l = 0; l <= k; l++) {
            const double shared = (c[k].a == c[l].a ? inverseMasses[c[k].a] : 0) + (c[k].b == c[l].b ? inverseMasses[c[k].b] : 0) -
                                  (c[k].a == c[l].b ? inverseMasses[c[k].a] : 0) - (c[k].b == c[l].a ? inverseMasses[c[k].b] : 0);
            K(k, l) = K(l, k) = shared * c[k].direction.dot(c[l].direction);
        }
    cluster.factors.compute(K);
    // K is semidefinite: a redundant constraint leaves a pivot of zero or rounding error against
    // the largest (LDLT pivots the largest first); its share of lambda is 0, not 0/0 or noise.
    const Eigen::VectorXd& D = cluster.factors.vectorD();
    const double tolerance = 1e-12 * D.cwiseAbs().maxCoeff();
    cluster.inversePivots = D.unaryExpr([tolerance](double d) { return d > tolerance ? 1 / d : 0.0; });
}

void ConstrainedPairImpulse::solve(const Cluster& cluster, Eigen::VectorXd& x) const {
    x = cluster.factors.transpositionsP() * x;
    cluster.factors.matrixL().solveInPlace(x);
    x.array() *= cluster.inversePivots.array();
    cluster.factors.matrixU().solveInPlace(x);
    x = cluster.factors.transpositionsP().transpose() * x;
}

double ConstrainedPairImpulse::addClusterResponse(const Cluster& cluster, const PairGeometry& p) const {
    auto impulseAt = [&](int particle) { return particle == p.i ? p.e : particle == p.j ? -p.e : Vec3(); };
    const std::vector<Constraint>& c = cluster.constraints;
    rhs.resize((Eigen::Index) c.size());
    for (size_t k = 0; k < c.size(); k++)
        rhs[k] = c[k].direction.dot(impulseAt(c[k].a) * inverseMasses[c[k].a] - impulseAt(c[k].b) * inverseMasses[c[k].b]);
    work = rhs;
    solve(cluster, work);
    double bLambda = 0;
    for (size_t k = 0; k < c.size(); k++) {
        bLambda += rhs[k] * work[k];
        spread.emplace_back(c[k].a, c[k].direction * (-work[k] * inverseMasses[c[k].a]));
        spread.emplace_back(c[k].b, c[k].direction * (work[k] * inverseMasses[c[k].b]));
    }
    return bLambda;
}

double ConstrainedPairImpulse::inverseReducedMass(const PairGeometry& p) const {
    const double free = inverseMasses[p.i] + inverseMasses[p.j];
    spread.assign({{p.i, p.e * inverseMasses[p.i]}, {p.j, -p.e * inverseMasses[p.j]}});
    double inverse = free;
    const int ci = clusterOf[p.i], cj = clusterOf[p.j];
    if (ci >= 0)
        inverse -= addClusterResponse(clusters[ci], p);
    if (cj >= 0 && cj != ci)
        inverse -= addClusterResponse(clusters[cj], p);
    return (inverse > 1e-9 * free ? inverse : 0.0);
}

void ConstrainedPairImpulse::apply(const PairGeometry& p, double impulse, std::vector<Vec3>& v) const {
    for (const std::pair<int, Vec3>& s : spread)
        v[s.first] += s.second * impulse;
}

void ConstrainedPairImpulse::applyAcross(const PairGeometry& p, const Vec3&, std::vector<Vec3>&) const {
    throw OpenMM::OpenMMException("transverse friction in a pairwise-sequential sweep is not available with constraints "
                                  "(pair " + std::to_string(p.i) + ", " + std::to_string(p.j) + ")");
}
