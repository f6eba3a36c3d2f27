#include "openmmdpd/internal/ForceTerms.h"
#include "openmm/CMAPTorsionForce.h"
#include "openmm/CustomAngleForce.h"
#include "openmm/CustomBondForce.h"
#include "openmm/CustomCentroidBondForce.h"
#include "openmm/CustomCompoundBondForce.h"
#include "openmm/CustomExternalForce.h"
#include "openmm/CustomHbondForce.h"
#include "openmm/CustomNonbondedForce.h"
#include "openmm/CustomTorsionForce.h"
#include "openmm/HarmonicAngleForce.h"
#include "openmm/HarmonicBondForce.h"
#include "openmm/PeriodicTorsionForce.h"
#include "openmm/RBTorsionForce.h"
#include "openmm/VirtualSite.h"
#include <algorithm>
#include <iterator>
#include <numeric>
#include <set>

using namespace DPDPlugin;

namespace {

// The terms of the forces that list the particles each term acts on, by kind of force: each
// calls `visit` for every term and returns true if `force` is of its kinds, else returns
// false.

bool visitBonds(const OpenMM::Force& force, const TermVisitor& visit) {
    Term term{"HarmonicBondForce", "bond", 0, {0, 0}};
    if (auto* bond = dynamic_cast<const OpenMM::HarmonicBondForce*>(&force)) {
        double length, kb;
        for (term.index = 0; term.index < bond->getNumBonds(); term.index++) {
            bond->getBondParameters(term.index, term.particles[0], term.particles[1], length, kb);
            visit(term);
        }
        return true;
    }
    if (auto* bond = dynamic_cast<const OpenMM::CustomBondForce*>(&force)) {
        term.forceClass = "CustomBondForce";
        std::vector<double> parameters;
        for (term.index = 0; term.index < bond->getNumBonds(); term.index++) {
            bond->getBondParameters(term.index, term.particles[0], term.particles[1], parameters);
            visit(term);
        }
        return true;
    }
    return false;
}

bool visitAngles(const OpenMM::Force& force, const TermVisitor& visit) {
    Term term{"HarmonicAngleForce", "angle", 0, {0, 0, 0}};
    std::vector<int>& p = term.particles;
    if (auto* angle = dynamic_cast<const OpenMM::HarmonicAngleForce*>(&force)) {
        double theta, ka;
        for (term.index = 0; term.index < angle->getNumAngles(); term.index++) {
            angle->getAngleParameters(term.index, p[0], p[1], p[2], theta, ka);
            visit(term);
        }
        return true;
    }
    if (auto* angle = dynamic_cast<const OpenMM::CustomAngleForce*>(&force)) {
        term.forceClass = "CustomAngleForce";
        std::vector<double> parameters;
        for (term.index = 0; term.index < angle->getNumAngles(); term.index++) {
            angle->getAngleParameters(term.index, p[0], p[1], p[2], parameters);
            visit(term);
        }
        return true;
    }
    return false;
}

bool visitTorsions(const OpenMM::Force& force, const TermVisitor& visit) {
    Term term{"PeriodicTorsionForce", "torsion", 0, {0, 0, 0, 0}};
    std::vector<int>& p = term.particles;
    if (auto* torsion = dynamic_cast<const OpenMM::PeriodicTorsionForce*>(&force)) {
        int periodicity;
        double phase, kt;
        for (term.index = 0; term.index < torsion->getNumTorsions(); term.index++) {
            torsion->getTorsionParameters(term.index, p[0], p[1], p[2], p[3], periodicity, phase, kt);
            visit(term);
        }
        return true;
    }
    if (auto* torsion = dynamic_cast<const OpenMM::RBTorsionForce*>(&force)) {
        term.forceClass = "RBTorsionForce";
        double c0, c1, c2, c3, c4, c5;
        for (term.index = 0; term.index < torsion->getNumTorsions(); term.index++) {
            torsion->getTorsionParameters(term.index, p[0], p[1], p[2], p[3], c0, c1, c2, c3, c4, c5);
            visit(term);
        }
        return true;
    }
    if (auto* torsion = dynamic_cast<const OpenMM::CustomTorsionForce*>(&force)) {
        term.forceClass = "CustomTorsionForce";
        std::vector<double> parameters;
        for (term.index = 0; term.index < torsion->getNumTorsions(); term.index++) {
            torsion->getTorsionParameters(term.index, p[0], p[1], p[2], p[3], parameters);
            visit(term);
        }
        return true;
    }
    return false;
}

/** CMAP: a pair of torsions, eight particles. */
bool visitCmapTorsions(const OpenMM::Force& force, const TermVisitor& visit) {
    auto* cmap = dynamic_cast<const OpenMM::CMAPTorsionForce*>(&force);
    if (cmap == nullptr)
        return false;
    Term term{"CMAPTorsionForce", "torsion pair", 0, std::vector<int>(8)};
    std::vector<int>& p = term.particles;
    int map;
    for (term.index = 0; term.index < cmap->getNumTorsions(); term.index++) {
        cmap->getTorsionParameters(term.index, map, p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7]);
        visit(term);
    }
    return true;
}

bool visitCompoundBonds(const OpenMM::Force& force, const TermVisitor& visit) {
    auto* compound = dynamic_cast<const OpenMM::CustomCompoundBondForce*>(&force);
    if (compound == nullptr)
        return false;
    Term term{"CustomCompoundBondForce", "bond", 0, {}};
    std::vector<double> parameters;
    for (term.index = 0; term.index < compound->getNumBonds(); term.index++) {
        compound->getBondParameters(term.index, term.particles, parameters);
        visit(term);
    }
    return true;
}

/** A centroid bond acts on every particle of the groups it joins (groups in no bond feel nothing). */
bool visitCentroidBonds(const OpenMM::Force& force, const TermVisitor& visit) {
    auto* centroid = dynamic_cast<const OpenMM::CustomCentroidBondForce*>(&force);
    if (centroid == nullptr)
        return false;
    Term term{"CustomCentroidBondForce", "bond", 0, {}};
    std::vector<int> groups, particles;
    std::vector<double> parameters, weights;
    for (term.index = 0; term.index < centroid->getNumBonds(); term.index++) {
        centroid->getBondParameters(term.index, groups, parameters);
        term.particles.clear();
        for (int g : groups) {
            centroid->getGroupParameters(g, particles, weights);
            term.particles.insert(term.particles.end(), particles.begin(), particles.end());
        }
        visit(term);
    }
    return true;
}

bool visitExternalParticles(const OpenMM::Force& force, const TermVisitor& visit) {
    auto* external = dynamic_cast<const OpenMM::CustomExternalForce*>(&force);
    if (external == nullptr)
        return false;
    Term term{"CustomExternalForce", "particle entry", 0, {0}};
    std::vector<double> parameters;
    for (term.index = 0; term.index < external->getNumParticles(); term.index++) {
        external->getParticleParameters(term.index, term.particles[0], parameters);
        visit(term);
    }
    return true;
}

/** Every donor interacts with every acceptor in range; unused slots (-1) are left out. */
bool visitHbondSites(const OpenMM::Force& force, const TermVisitor& visit) {
    auto* hbond = dynamic_cast<const OpenMM::CustomHbondForce*>(&force);
    if (hbond == nullptr)
        return false;
    std::vector<double> parameters;
    int p[3];
    const auto visitSite = [&](const char* kind, int index) {
        Term term{"CustomHbondForce", kind, index, {}};
        std::copy_if(p, p + 3, std::back_inserter(term.particles), [](int i) { return i >= 0; });
        visit(term);
    };
    for (int k = 0; k < hbond->getNumDonors(); k++) {
        hbond->getDonorParameters(k, p[0], p[1], p[2], parameters);
        visitSite("donor", k);
    }
    for (int k = 0; k < hbond->getNumAcceptors(); k++) {
        hbond->getAcceptorParameters(k, p[0], p[1], p[2], parameters);
        visitSite("acceptor", k);
    }
    return true;
}

/** A CustomNonbondedForce lists its particles only through interaction groups; without any it acts on all. */
bool visitInteractionGroups(const OpenMM::Force& force, const TermVisitor& visit) {
    auto* nonbonded = dynamic_cast<const OpenMM::CustomNonbondedForce*>(&force);
    if (nonbonded == nullptr || nonbonded->getNumInteractionGroups() == 0)
        return false;
    Term term{"CustomNonbondedForce", "interaction group", 0, {}};
    for (term.index = 0; term.index < nonbonded->getNumInteractionGroups(); term.index++) {
        std::set<int> set1, set2;
        nonbonded->getInteractionGroupParameters(term.index, set1, set2);
        term.particles.assign(set1.begin(), set1.end());
        term.particles.insert(term.particles.end(), set2.begin(), set2.end());
        visit(term);
    }
    return true;
}

/** The terms of the bonded forces (isBondedForce): those that join particles into molecules. */
bool forEachBondedTerm(const OpenMM::Force& force, const TermVisitor& visit) {
    return visitBonds(force, visit) || visitAngles(force, visit) || visitTorsions(force, visit) ||
           visitCmapTorsions(force, visit) || visitCompoundBonds(force, visit) || visitCentroidBonds(force, visit);
}

/** Union-find over particles: each set is a molecule. */
class Molecules {
public:
    explicit Molecules(int n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
    int root(int i) {
        while (parent[i] != i)
            i = parent[i] = parent[parent[i]];
        return i;
    }
    void join(int i, int j) {
        const int a = root(i), b = root(j);
        parent[std::max(a, b)] = std::min(a, b);
    }
    void joinAll(const std::vector<int>& particles) {
        for (size_t k = 1; k < particles.size(); k++)
            join(particles[0], particles[k]);
    }

private:
    std::vector<int> parent;
};

} // namespace

bool DPDPlugin::forEachTerm(const OpenMM::Force& force, const TermVisitor& visit) {
    return forEachBondedTerm(force, visit) || visitExternalParticles(force, visit) || visitHbondSites(force, visit) ||
           visitInteractionGroups(force, visit);
}

bool DPDPlugin::isBondedForce(const OpenMM::Force& force) {
    return dynamic_cast<const OpenMM::HarmonicBondForce*>(&force) || dynamic_cast<const OpenMM::CustomBondForce*>(&force) ||
           dynamic_cast<const OpenMM::HarmonicAngleForce*>(&force) || dynamic_cast<const OpenMM::CustomAngleForce*>(&force) ||
           dynamic_cast<const OpenMM::PeriodicTorsionForce*>(&force) || dynamic_cast<const OpenMM::RBTorsionForce*>(&force) ||
           dynamic_cast<const OpenMM::CustomTorsionForce*>(&force) || dynamic_cast<const OpenMM::CMAPTorsionForce*>(&force) ||
           dynamic_cast<const OpenMM::CustomCompoundBondForce*>(&force) ||
           dynamic_cast<const OpenMM::CustomCentroidBondForce*>(&force);
}

std::vector<std::vector<int>> DPDPlugin::findMolecules(const OpenMM::System& system) {
    const int n = system.getNumParticles();
    Molecules molecules(n);
    for (int f = 0; f < system.getNumForces(); f++)
        forEachBondedTerm(system.getForce(f), [&](const Term& term) { molecules.joinAll(term.particles); });
    for (int k = 0; k < system.getNumConstraints(); k++) {
        int i, j;
        double distance;
        system.getConstraintParameters(k, i, j, distance);
        molecules.join(i, j);
    }
    for (int i = 0; i < n; i++)
        if (system.isVirtualSite(i)) {
            const OpenMM::VirtualSite& site = system.getVirtualSite(i);
            for (int k = 0; k < site.getNumParticles(); k++)
                molecules.join(i, site.getParticle(k));
        }
    // Roots are each molecule's smallest particle, so numbering them in order of first particle is one pass.
    std::vector<int> index(n, -1);
    std::vector<std::vector<int>> result;
    for (int i = 0; i < n; i++) {
        const int r = molecules.root(i);
        if (index[r] < 0) {
            index[r] = (int) result.size();
            result.emplace_back();
        }
        result[index[r]].push_back(i);
    }
    return result;
}
