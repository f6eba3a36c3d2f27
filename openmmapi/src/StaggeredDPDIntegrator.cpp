#include "openmmdpd/StaggeredDPDIntegrator.h"
#include "openmmdpd/DPDKernels.h"
#include "openmmdpd/internal/ForceTerms.h"
#include "openmmdpd/internal/ParameterChecks.h"
#include "openmm/CustomNonbondedForce.h"
#include "openmm/OpenMMException.h"
#include "openmm/System.h"
#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>

using namespace DPDPlugin;
using OpenMM::OpenMMException;

namespace {

void requireRelaxation(double value, const char* name) {
    require(std::isfinite(value) && value >= -1 && value <= 1,
            std::string("StaggeredDPDIntegrator: ") + name + " must be in [-1, 1], got " + numberText(value));
}

bool isFast(const OpenMM::Force& force, int fastForceGroups) {
    return (fastForceGroups & (1 << force.getForceGroup())) != 0;
}

/** "force 3 (FENE, group 1)": where a force is in the System, for error messages. */
std::string forcePlace(const OpenMM::Force& force, int index) {
    std::string name = force.getName();
    return "force " + std::to_string(index) + " (" + (name.empty() ? "unnamed" : name) + ", group " +
           std::to_string(force.getForceGroup()) + ")";
}

/** "HarmonicBondForce (force 2, group 1)", with the force's name when it is not the class name. */
std::string termForceText(const Term& term, const OpenMM::Force& force, int index) {
    std::string text = term.forceClass;
    if (!force.getName().empty() && force.getName() != term.forceClass)
        text += " \"" + force.getName() + "\"";
    return text + " (force " + std::to_string(index) + ", group " + std::to_string(force.getForceGroup()) + ")";
}

/** Why the polymer cannot be derived from force `index`, which lists no particles. */
std::string underivableMessage(const OpenMM::Force& force, int index) {
    if (dynamic_cast<const OpenMM::CustomNonbondedForce*>(&force) != nullptr)
        return "StaggeredDPDIntegrator: " + forcePlace(force, index) + " in a fast force group is a CustomNonbondedForce "
               "without interaction groups, which acts on every particle; give it interaction groups (polymer with "
               "polymer), or set the polymer particles explicitly with setPolymerParticles()";
    return "StaggeredDPDIntegrator: cannot tell which particles " + forcePlace(force, index) + " in a fast force group acts "
           "on; set the polymer particles explicitly with setPolymerParticles()";
}

/** The particles of the terms of the fast forces; throws if a fast force lists none. */
std::set<int> deriveFastParticles(const OpenMM::System& system, int fastForceGroups) {
    std::set<int> found;
    for (int f = 0; f < system.getNumForces(); f++) {
        const OpenMM::Force& force = system.getForce(f);
        if (isFast(force, fastForceGroups) &&
            !forEachTerm(force, [&](const Term& term) { found.insert(term.particles.begin(), term.particles.end()); }))
            throw OpenMMException(underivableMessage(force, f));
    }
    return found;
}

/**
 * Throws, naming the force, the term and the particle, if a term of a fast force acts on a
 * particle outside `polymer`.  Fast forces that list no particles are left to the platforms'
 * check of the forces at every evaluation (fastForcesListTheirParticles()).
 */
void requireFastTermsInPolymer(const OpenMM::System& system, int fastForceGroups, const std::set<int>& polymer) {
    for (int f = 0; f < system.getNumForces(); f++) {
        const OpenMM::Force& force = system.getForce(f);
        if (!isFast(force, fastForceGroups))
            continue;
        forEachTerm(force, [&](const Term& term) {
            for (int p : term.particles)
                if (polymer.count(p) == 0)  // (the message is built only then: a System may have 10^6 terms)
                    throw OpenMMException("StaggeredDPDIntegrator: particle " + std::to_string(p) + " is in " + term.kind +
                                          " " + std::to_string(term.index) + " of " + termForceText(term, force, f) +
                                          " but not in the polymer particles; add it with setPolymerParticles(), or move "
                                          "that force out of the fast force groups");
        });
    }
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
    require(steps >= 1 && steps <= MAX_SUB_STEPS, "StaggeredDPDIntegrator: numSubSteps (K) must be from 1 to " +
            std::to_string(MAX_SUB_STEPS) + ", got " + std::to_string(steps));
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
    if (polymerParticles.empty()) {
        const std::set<int> derived = deriveFastParticles(system, fastForceGroups);
        require(!derived.empty(), "StaggeredDPDIntegrator: the forces in the fast force groups act on no particle, so there is "
                "no polymer to sub-cycle; put the stiff polymer forces in a fast group, or set the polymer particles explicitly "
                "with setPolymerParticles()");
        return std::vector<int>(derived.begin(), derived.end());
    }
    for (int p : polymerParticles)
        require(p < n, "StaggeredDPDIntegrator: polymer particle " + std::to_string(p) + " is not in the System (" +
                std::to_string(n) + " particles)");
    const std::set<int> polymer(polymerParticles.begin(), polymerParticles.end());
    requireFastTermsInPolymer(system, fastForceGroups, polymer);
    return std::vector<int>(polymer.begin(), polymer.end());
}

bool StaggeredDPDIntegrator::fastForcesListTheirParticles(const OpenMM::System& system) const {
    for (int f = 0; f < system.getNumForces(); f++)
        if (isFast(system.getForce(f), fastForceGroups) && !forEachTerm(system.getForce(f), [](const Term&) {}))
            return false;
    return true;
}

void StaggeredDPDIntegrator::validate(const OpenMM::System& system) const {
    DPDThermostatIntegrator::validate(system);
    // The polymer sub-cycle moves the polymer alone, against forces from side Contexts that
    // know neither constraints nor virtual sites: refused rather than integrated wrongly.
    require(system.getNumConstraints() == 0, "StaggeredDPDIntegrator: the System must have no constraints (the polymer "
            "sub-cycle cannot apply them), got " + std::to_string(system.getNumConstraints()) + "; DPDVVIntegrator, "
            "ShardlowIntegrator, LoweAndersenIntegrator and EDPDIntegrator support constraints");
    int sites = 0;
    for (int i = 0; i < system.getNumParticles(); i++)
        sites += system.isVirtualSite(i) ? 1 : 0;
    require(sites == 0, "StaggeredDPDIntegrator: the System must have no virtual sites (the polymer sub-cycle cannot "
            "place them), got " + std::to_string(sites) + "; DPDVVIntegrator, ShardlowIntegrator, LoweAndersenIntegrator "
            "and EDPDIntegrator support virtual sites");
    require((fastForceGroups & ~getIntegrationForceGroups()) == 0,
            "StaggeredDPDIntegrator: fastForceGroups (" + std::to_string(fastForceGroups) + ") must be a subset of the "
            "integration force groups (" + std::to_string(getIntegrationForceGroups()) + ")");
    bool anyFast = false;
    for (int f = 0; f < system.getNumForces(); f++)
        anyFast = anyFast || isFast(system.getForce(f), fastForceGroups);
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
