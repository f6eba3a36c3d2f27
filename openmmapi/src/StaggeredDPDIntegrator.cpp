#include "openmmdpd/StaggeredDPDIntegrator.h"
#include "openmmdpd/DPDKernels.h"
#include "openmmdpd/internal/ParameterChecks.h"
#include "openmm/CustomAngleForce.h"
#include "openmm/CustomBondForce.h"
#include "openmm/CustomCompoundBondForce.h"
#include "openmm/CustomNonbondedForce.h"
#include "openmm/CustomTorsionForce.h"
#include "openmm/HarmonicAngleForce.h"
#include "openmm/HarmonicBondForce.h"
#include "openmm/OpenMMException.h"
#include "openmm/PeriodicTorsionForce.h"
#include "openmm/RBTorsionForce.h"
#include "openmm/System.h"
#include <algorithm>
#include <cmath>
#include <set>
#include <typeinfo>

using namespace DPDPlugin;
using OpenMM::OpenMMException;

namespace {

void requireRelaxation(double value, const char* name) {
    require(std::isfinite(value) && value >= -1 && value <= 1,
            std::string("StaggeredDPDIntegrator: ") + name + " must be in [-1, 1], got " + numberText(value));
}

std::string forceName(const OpenMM::Force& force, int index) {
    std::string name = force.getName();
    return "force " + std::to_string(index) + " (" + (name.empty() ? "unnamed" : name) + ")";
}

// The particles of the terms of a fast force, by kind of force: each adds them to `found` and
// returns true if `force` is of its kinds, else returns false.

bool addBondParticles(const OpenMM::Force& force, std::set<int>& found) {
    int i, j;
    if (auto* bond = dynamic_cast<const OpenMM::HarmonicBondForce*>(&force)) {
        double length, kb;
        for (int k = 0; k < bond->getNumBonds(); k++) {
            bond->getBondParameters(k, i, j, length, kb);
            found.insert({i, j});
        }
        return true;
    }
    if (auto* bond = dynamic_cast<const OpenMM::CustomBondForce*>(&force)) {
        std::vector<double> parameters;
        for (int k = 0; k < bond->getNumBonds(); k++) {
            bond->getBondParameters(k, i, j, parameters);
            found.insert({i, j});
        }
        return true;
    }
    return false;
}

bool addAngleParticles(const OpenMM::Force& force, std::set<int>& found) {
    int i, j, l;
    if (auto* angle = dynamic_cast<const OpenMM::HarmonicAngleForce*>(&force)) {
        double theta, ka;
        for (int k = 0; k < angle->getNumAngles(); k++) {
            angle->getAngleParameters(k, i, j, l, theta, ka);
            found.insert({i, j, l});
        }
        return true;
    }
    if (auto* angle = dynamic_cast<const OpenMM::CustomAngleForce*>(&force)) {
        std::vector<double> parameters;
        for (int k = 0; k < angle->getNumAngles(); k++) {
            angle->getAngleParameters(k, i, j, l, parameters);
            found.insert({i, j, l});
        }
        return true;
    }
    return false;
}

bool addTorsionParticles(const OpenMM::Force& force, std::set<int>& found) {
    int i, j, l, m;
    if (auto* torsion = dynamic_cast<const OpenMM::PeriodicTorsionForce*>(&force)) {
        int periodicity;
        double phase, kt;
        for (int k = 0; k < torsion->getNumTorsions(); k++) {
            torsion->getTorsionParameters(k, i, j, l, m, periodicity, phase, kt);
            found.insert({i, j, l, m});
        }
        return true;
    }
    if (auto* torsion = dynamic_cast<const OpenMM::RBTorsionForce*>(&force)) {
        double c0, c1, c2, c3, c4, c5;
        for (int k = 0; k < torsion->getNumTorsions(); k++) {
            torsion->getTorsionParameters(k, i, j, l, m, c0, c1, c2, c3, c4, c5);
            found.insert({i, j, l, m});
        }
        return true;
    }
    if (auto* torsion = dynamic_cast<const OpenMM::CustomTorsionForce*>(&force)) {
        std::vector<double> parameters;
        for (int k = 0; k < torsion->getNumTorsions(); k++) {
            torsion->getTorsionParameters(k, i, j, l, m, parameters);
            found.insert({i, j, l, m});
        }
        return true;
    }
    return false;
}

bool addCompoundBondParticles(const OpenMM::Force& force, std::set<int>& found) {
    auto* compound = dynamic_cast<const OpenMM::CustomCompoundBondForce*>(&force);
    if (compound == nullptr)
        return false;
    std::vector<int> particles;
    std::vector<double> parameters;
    for (int k = 0; k < compound->getNumBonds(); k++) {
        compound->getBondParameters(k, particles, parameters);
        found.insert(particles.begin(), particles.end());
    }
    return true;
}

/** A CustomNonbondedForce acts on its interaction groups; without any, on every particle (an error). */
bool addInteractionGroupParticles(const OpenMM::Force& force, int index, std::set<int>& found) {
    auto* nonbonded = dynamic_cast<const OpenMM::CustomNonbondedForce*>(&force);
    if (nonbonded == nullptr)
        return false;
    require(nonbonded->getNumInteractionGroups() > 0,
            "StaggeredDPDIntegrator: " + forceName(force, index) + " in a fast force group is a CustomNonbondedForce "
            "without interaction groups, which acts on every particle; give it interaction groups (polymer with "
            "polymer), or set the polymer particles explicitly with setPolymerParticles()");
    for (int g = 0; g < nonbonded->getNumInteractionGroups(); g++) {
        std::set<int> set1, set2;
        nonbonded->getInteractionGroupParameters(g, set1, set2);
        found.insert(set1.begin(), set1.end());
        found.insert(set2.begin(), set2.end());
    }
    return true;
}

/** Adds the particles force `index` of the System acts on to `found`; throws if it cannot tell. */
void addParticlesOf(const OpenMM::Force& force, int index, std::set<int>& found) {
    if (addBondParticles(force, found) || addAngleParticles(force, found) || addTorsionParticles(force, found) ||
        addCompoundBondParticles(force, found) || addInteractionGroupParticles(force, index, found))
        return;
    throw OpenMMException("StaggeredDPDIntegrator: cannot tell which particles " + forceName(force, index) +
                          " in a fast force group acts on; set the polymer particles explicitly with "
                          "setPolymerParticles()");
}

} // namespace

StaggeredDPDIntegrator::StaggeredDPDIntegrator(double temperature, double defaultFriction, double defaultCutoff, double stepSize,
                                               int numSubSteps) :
        DPDThermostatIntegrator("StaggeredDPDIntegrator", temperature, defaultFriction, defaultCutoff, stepSize),
        baseScheme(VelocityVerlet), numSubSteps(1), fastForceGroups(1 << 1), lambda(0.65), mu(0), a(0.6), b(0), weighted(true) {
    setNumSubSteps(numSubSteps);
}

void StaggeredDPDIntegrator::setBaseScheme(BaseScheme scheme) {
    require(scheme == VelocityVerlet || scheme == LoweAndersen,
            "StaggeredDPDIntegrator: baseScheme must be VelocityVerlet (0) or LoweAndersen (1), got " + std::to_string((int) scheme));
    baseScheme = scheme;
}

void StaggeredDPDIntegrator::setNumSubSteps(int steps) {
    require(steps >= 1, "StaggeredDPDIntegrator: numSubSteps (K) must be >= 1, got " + std::to_string(steps));
    numSubSteps = steps;
}

void StaggeredDPDIntegrator::setLambda(double value) {
    require(std::isfinite(value) && value >= 0 && value <= 1, "StaggeredDPDIntegrator: lambda must be in [0, 1], got " + numberText(value));
    lambda = value;
}

void StaggeredDPDIntegrator::setMu(double value) {
    requireRelaxation(value, "mu");
    mu = value;
}

void StaggeredDPDIntegrator::setA(double value) {
    requireRelaxation(value, "a");
    a = value;
}

void StaggeredDPDIntegrator::setB(double value) {
    requireRelaxation(value, "b");
    b = value;
}

void StaggeredDPDIntegrator::setRelaxationParameters(double muValue, double aValue, double bValue) {
    requireRelaxation(muValue, "mu");
    requireRelaxation(aValue, "a");
    requireRelaxation(bValue, "b");
    mu = muValue;
    a = aValue;
    b = bValue;
}

void StaggeredDPDIntegrator::setFastForceGroups(int groups) {
    require(groups != 0, "StaggeredDPDIntegrator: fastForceGroups must name at least one force group (a non-zero bitmask), got 0");
    fastForceGroups = groups;
}

void StaggeredDPDIntegrator::useRecommendedParameters() {
    weighted = true;
    if (baseScheme == VelocityVerlet) {
        mu = 0;
        a = 0.6;
        b = 0;
        lambda = 0.65;
    }
    else {
        mu = 0;
        a = 0;
        b = 0.4;
    }
}

void StaggeredDPDIntegrator::setPolymerParticles(const std::vector<int>& particles) {
    for (int p : particles)
        require(p >= 0, "StaggeredDPDIntegrator: polymer particle indices must be >= 0, got " + std::to_string(p));
    polymerParticles = particles;
}

void StaggeredDPDIntegrator::addPolymerParticle(int particle) {
    require(particle >= 0, "StaggeredDPDIntegrator: polymer particle indices must be >= 0, got " + std::to_string(particle));
    polymerParticles.push_back(particle);
}

std::vector<int> StaggeredDPDIntegrator::findPolymerParticles(const OpenMM::System& system) const {
    const int n = system.getNumParticles();
    std::set<int> found;
    if (!polymerParticles.empty()) {
        for (int p : polymerParticles) {
            require(p < n, "StaggeredDPDIntegrator: polymer particle " + std::to_string(p) + " is not in the System (" +
                    std::to_string(n) + " particles)");
            found.insert(p);
        }
        return std::vector<int>(found.begin(), found.end());
    }
    for (int f = 0; f < system.getNumForces(); f++)
        if ((fastForceGroups & (1 << system.getForce(f).getForceGroup())) != 0)
            addParticlesOf(system.getForce(f), f, found);
    require(!found.empty(), "StaggeredDPDIntegrator: the forces in the fast force groups act on no particle, so there is no "
            "polymer to sub-cycle; put the stiff polymer forces in a fast group, or set the polymer particles explicitly with "
            "setPolymerParticles()");
    return std::vector<int>(found.begin(), found.end());
}

void StaggeredDPDIntegrator::validate(const OpenMM::System& system) const {
    DPDThermostatIntegrator::validate(system);
    require((fastForceGroups & ~getIntegrationForceGroups()) == 0,
            "StaggeredDPDIntegrator: fastForceGroups (" + std::to_string(fastForceGroups) + ") must be a subset of the "
            "integration force groups (" + std::to_string(getIntegrationForceGroups()) + ")");
    bool anyFast = false;
    for (int f = 0; f < system.getNumForces(); f++)
        anyFast = anyFast || (fastForceGroups & (1 << system.getForce(f).getForceGroup())) != 0;
    require(anyFast, "StaggeredDPDIntegrator: no force of the System is in a fast force group (fastForceGroups = " +
            std::to_string(fastForceGroups) + "); put the stiff polymer forces in one, e.g. force.setForceGroup(1)");
    for (int p : polymerParticles)
        require(p < system.getNumParticles(), "StaggeredDPDIntegrator: polymer particle " + std::to_string(p) +
                " is not in the System (" + std::to_string(system.getNumParticles()) + " particles)");
    // Gamma Dt is a probability.
    if (baseScheme == LoweAndersen && getMaxFriction() * getStepSize() > 1) {
        throw OpenMMException("StaggeredDPDIntegrator: with the LoweAndersen base, Gamma Dt must be <= 1 (it is a collision "
                              "probability), got the largest Gamma (" + numberText(getMaxFriction()) + " /ps) times the outer "
                              "step size (" + numberText(getStepSize()) + " ps) = " + numberText(getMaxFriction() * getStepSize()));
    }
}

std::string StaggeredDPDIntegrator::kernelName() const {
    return IntegrateStaggeredDPDStepKernel::Name();
}

void StaggeredDPDIntegrator::initializeStepKernel(OpenMM::Kernel& kernel, const OpenMM::System& system) const {
    kernel.getAs<IntegrateStaggeredDPDStepKernel>().initialize(system, *this);
}

void StaggeredDPDIntegrator::executeStepKernel(OpenMM::Kernel& kernel, OpenMM::ContextImpl& context) const {
    kernel.getAs<IntegrateStaggeredDPDStepKernel>().execute(context, *this);
}
