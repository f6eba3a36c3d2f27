#include "openmmdpd/CheckpointIO.h"
#include "openmmdpd/StaggeredDynamics.h"
#include "openmmdpd/PairEvaluators.h"
#include "openmmdpd/DPDSoftRepulsionForce.h"
#include "openmm/CustomBondForce.h"
#include "openmm/CustomNonbondedForce.h"
#include "openmm/HarmonicBondForce.h"
#include "openmm/OpenMMException.h"
#include "openmm/Platform.h"
#include "openmm/State.h"
#include "openmm/System.h"
#include "openmm/serialization/XmlSerializer.h"
#include <algorithm>
#include <istream>
#include <map>
#include <ostream>
#include <set>

using namespace DPDPlugin;
using OpenMM::Vec3;

StaggeredDynamics::StaggeredDynamics(const OpenMM::System& system, const StaggeredDPDIntegrator& integrator, ParallelExecutor& executor) :
        // The Lowe base sweeps pairs sequentially, in the colour order LoweAndersenIntegrator uses.
        PairDynamics(system, integrator, executor, integrator.getBaseScheme() == StaggeredDPDIntegrator::LoweAndersen ? 3 : 1),
        baseScheme(integrator.getBaseScheme()), pairSweep(executor), fastContextTried(false),
        numSubSteps(integrator.getNumSubSteps()) {
    const int n = system.getNumParticles();
    for (auto* v : {&predicted, &newForce})
        v->resize(n);
    updatePolymer(system, integrator);
}

void StaggeredDynamics::updatePolymer(const OpenMM::System& system, const StaggeredDPDIntegrator& integrator) {
    polymer.select(system, integrator);
    for (auto* v : {&fastForce, &newFastForce, &startPositions, &startVelocities, &drivingForce, &fastPositions})
        v->assign(polymer.particles.size(), Vec3());
    fastContext.reset();
    fastIntegrator.reset();
    fastSystem.reset();
    slowContext.reset();
    slowIntegrator.reset();
    slowSystem.reset();
    fastContextTried = false;
}

namespace {

// Copies of the fast forces over the polymer particles only (particle i becomes index[i],
// -1 for a particle outside the polymer), for the Context of the polymer alone: each returns
// null when the force touches a particle outside the polymer or cannot be copied faithfully.

OpenMM::Force* copyHarmonicBonds(const OpenMM::HarmonicBondForce& bond, const std::vector<int>& index) {
    std::unique_ptr<OpenMM::HarmonicBondForce> copy(new OpenMM::HarmonicBondForce());
    for (int k = 0; k < bond.getNumBonds(); k++) {
        int i, j;
        double length, kb;
        bond.getBondParameters(k, i, j, length, kb);
        if (index[i] < 0 || index[j] < 0)
            return nullptr;
        copy->addBond(index[i], index[j], length, kb);
    }
    copy->setUsesPeriodicBoundaryConditions(bond.usesPeriodicBoundaryConditions());
    return copy.release();
}

OpenMM::Force* copyCustomBonds(const OpenMM::CustomBondForce& bond, const std::vector<int>& index) {
    if (bond.getNumEnergyParameterDerivatives() > 0)
        return nullptr;
    std::unique_ptr<OpenMM::CustomBondForce> copy(new OpenMM::CustomBondForce(bond.getEnergyFunction()));
    for (int p = 0; p < bond.getNumPerBondParameters(); p++)
        copy->addPerBondParameter(bond.getPerBondParameterName(p));
    for (int p = 0; p < bond.getNumGlobalParameters(); p++)
        copy->addGlobalParameter(bond.getGlobalParameterName(p), bond.getGlobalParameterDefaultValue(p));
    std::vector<double> parameters;
    for (int k = 0; k < bond.getNumBonds(); k++) {
        int i, j;
        bond.getBondParameters(k, i, j, parameters);
        if (index[i] < 0 || index[j] < 0)
            return nullptr;
        copy->addBond(index[i], index[j], parameters);
    }
    copy->setUsesPeriodicBoundaryConditions(bond.usesPeriodicBoundaryConditions());
    return copy.release();
}

/** A CustomNonbondedForce with the energy, parameters, functions and settings of `force`, and no particles. */
OpenMM::CustomNonbondedForce* emptyNonbondedLike(const OpenMM::CustomNonbondedForce& force) {
    std::unique_ptr<OpenMM::CustomNonbondedForce> copy(new OpenMM::CustomNonbondedForce(force.getEnergyFunction()));
    for (int p = 0; p < force.getNumPerParticleParameters(); p++)
        copy->addPerParticleParameter(force.getPerParticleParameterName(p));
    for (int p = 0; p < force.getNumGlobalParameters(); p++)
        copy->addGlobalParameter(force.getGlobalParameterName(p), force.getGlobalParameterDefaultValue(p));
    for (int f = 0; f < force.getNumTabulatedFunctions(); f++)
        copy->addTabulatedFunction(force.getTabulatedFunctionName(f),
                                   OpenMM::XmlSerializer::clone<OpenMM::TabulatedFunction>(force.getTabulatedFunction(f)));
    copy->setNonbondedMethod(force.getNonbondedMethod());
    copy->setCutoffDistance(force.getCutoffDistance());
    copy->setUseSwitchingFunction(force.getUseSwitchingFunction());
    copy->setSwitchingDistance(force.getSwitchingDistance());
#if OPENMMDPD_OPENMM_MAJOR >= 8
    // Per-particle values computed from the parameters (OpenMM 8): without them the copy's
    // energy names unknown variables and the polymer Context could not be made.
    for (int v = 0; v < force.getNumComputedValues(); v++) {
        std::string name, expression;
        force.getComputedValueParameters(v, name, expression);
        copy->addComputedValue(name, expression);
    }
#endif
    return copy.release();
}

/** The particles (in polymer order: index[particles[k]] == k) and the exclusions within the polymer. */
void copyNonbondedParticles(const OpenMM::CustomNonbondedForce& force, const std::vector<int>& index,
                            OpenMM::CustomNonbondedForce& copy) {
    std::vector<double> parameters;
    for (size_t i = 0; i < index.size(); i++)
        if (index[i] >= 0) {
            force.getParticleParameters((int) i, parameters);
            copy.addParticle(parameters);
        }
    for (int k = 0; k < force.getNumExclusions(); k++) {
        int i, j;
        force.getExclusionParticles(k, i, j);
        if (index[i] >= 0 && index[j] >= 0)
            copy.addExclusion(index[i], index[j]);
    }
}

/** Whether the force's one interaction group is every polymer particle with every other. */
bool isWholePolymerGroup(const OpenMM::CustomNonbondedForce& force, const std::vector<int>& index, size_t numPolymer) {
    if (force.getNumInteractionGroups() != 1)
        return false;
    std::set<int> set1, set2;
    force.getInteractionGroupParameters(0, set1, set2);
    return set1 == set2 && set1.size() == numPolymer && std::all_of(set1.begin(), set1.end(), [&](int i) { return index[i] >= 0; });
}

/** set, renumbered by index; false if a particle is outside the polymer. */
bool mapToPolymer(const std::set<int>& set, const std::vector<int>& index, std::set<int>& mapped) {
    for (int i : set) {
        if (index[i] < 0)
            return false;
        mapped.insert(index[i]);
    }
    return true;
}

/** The interaction groups, renumbered; false if one reaches outside the polymer. */
bool copyInteractionGroups(const OpenMM::CustomNonbondedForce& force, const std::vector<int>& index,
                           OpenMM::CustomNonbondedForce& copy) {
    for (int g = 0; g < force.getNumInteractionGroups(); g++) {
        std::set<int> set1, set2, mapped1, mapped2;
        force.getInteractionGroupParameters(g, set1, set2);
        if (!mapToPolymer(set1, index, mapped1) || !mapToPolymer(set2, index, mapped2))
            return false;
        copy.addInteractionGroup(mapped1, mapped2);
    }
    return true;
}

OpenMM::Force* copyCustomNonbonded(const OpenMM::CustomNonbondedForce& nonbonded, const std::vector<int>& index) {
    // Only interaction groups confine it to the polymer; a long-range correction depends on
    // the whole System.
    if (nonbonded.getNumInteractionGroups() == 0 || nonbonded.getUseLongRangeCorrection() ||
        nonbonded.getNumEnergyParameterDerivatives() > 0)
        return nullptr;
    std::unique_ptr<OpenMM::CustomNonbondedForce> copy(emptyNonbondedLike(nonbonded));
    copyNonbondedParticles(nonbonded, index, *copy);
    // One group of every polymer particle with every other is no restriction in the copy:
    // leave it out, so that OpenMM uses its neighbour list rather than all pairs.
    if (!isWholePolymerGroup(nonbonded, index, (size_t) copy->getNumParticles()) &&
        !copyInteractionGroups(nonbonded, index, *copy))
        return nullptr;
    return copy.release();
}

} // namespace

OpenMM::Force* DPDPlugin::copyOverPolymer(const OpenMM::Force& force, const std::vector<int>& index) {
    if (auto* bond = dynamic_cast<const OpenMM::HarmonicBondForce*>(&force))
        return copyHarmonicBonds(*bond, index);
    if (auto* bond = dynamic_cast<const OpenMM::CustomBondForce*>(&force))
        return copyCustomBonds(*bond, index);
    if (auto* nonbonded = dynamic_cast<const OpenMM::CustomNonbondedForce*>(&force))
        return copyCustomNonbonded(*nonbonded, index);
    return nullptr;
}

namespace {

/** The platform properties of a Context (threads, determinism, ...), for Contexts beside it. */
std::map<std::string, std::string> contextProperties(OpenMM::ContextImpl& context) {
    std::map<std::string, std::string> properties;
    const OpenMM::Platform& platform = context.getPlatform();
    for (const std::string& name : platform.getPropertyNames())
        properties[name] = platform.getPropertyValue(context.getOwner(), name);
    return properties;
}

} // namespace

void StaggeredDynamics::makeFastContext(OpenMM::ContextImpl& context, const StaggeredDPDIntegrator& integrator) {
    fastContextTried = true;
    const OpenMM::System& system = context.getSystem();
    std::unique_ptr<OpenMM::System> reduced(new OpenMM::System());
    for (int p : polymer.particles)
        reduced->addParticle(system.getParticleMass(p));
    Vec3 box[3];
    system.getDefaultPeriodicBoxVectors(box[0], box[1], box[2]);
    reduced->setDefaultPeriodicBoxVectors(box[0], box[1], box[2]);
    for (int f = 0; f < system.getNumForces(); f++) {
        const OpenMM::Force& force = system.getForce(f);
        if ((integrator.getFastForceGroups() & (1 << force.getForceGroup())) == 0)
            continue;
        OpenMM::Force* copy = copyOverPolymer(force, polymer.index);
        if (copy == nullptr)
            return;  // the full Context evaluates the fast groups
        reduced->addForce(copy);
    }
    if (reduced->getNumForces() == 0)
        return;
    fastSystem = std::move(reduced);
    fastIntegrator.reset(new OpenMM::VerletIntegrator(1.0));
    fastContext.reset(new OpenMM::Context(*fastSystem, *fastIntegrator, context.getPlatform(), contextProperties(context)));
    fastContext->getState(0).getPeriodicBoxVectors(fastBox[0], fastBox[1], fastBox[2]);
    makeSlowContext(context, integrator);
}

void StaggeredDynamics::makeSlowContext(OpenMM::ContextImpl& context, const StaggeredDPDIntegrator& integrator) {
    std::unique_ptr<OpenMM::System> system(OpenMM::XmlSerializer::clone<OpenMM::System>(context.getSystem()));
    // A soft force that the thermostat pairs can carry is added from them (as at K = 1), not
    // searched again here.
    slowOmitsSoftForce = (softForceToFuse(context, slowGroups(integrator)) != nullptr);
    for (int f = system->getNumForces() - 1; f >= 0; f--)
        if ((integrator.getFastForceGroups() & (1 << system->getForce(f).getForceGroup())) != 0 ||
            (slowOmitsSoftForce && dynamic_cast<const DPDSoftRepulsionForce*>(&system->getForce(f)) != nullptr))
            system->removeForce(f);
    slowContext.reset();
    if (system->getNumForces() == 0)
        return;  // nothing left for it: the main Context's path skips the evaluation
    slowSystem = std::move(system);
    slowIntegrator.reset(new OpenMM::VerletIntegrator(1.0));
    slowContext.reset(new OpenMM::Context(*slowSystem, *slowIntegrator, context.getPlatform(), contextProperties(context)));
    slowContext->getState(0).getPeriodicBoxVectors(slowBox[0], slowBox[1], slowBox[2]);
}

void StaggeredDynamics::syncContext(OpenMM::ContextImpl& context, OpenMM::Context& target, Vec3* box) {
    Vec3 current[3];
    context.getPeriodicBoxVectors(current[0], current[1], current[2]);
    if (current[0] != box[0] || current[1] != box[1] || current[2] != box[2]) {
        target.setPeriodicBoxVectors(current[0], current[1], current[2]);
        std::copy(current, current + 3, box);
    }
    const std::map<std::string, double>& targetParameters = target.getParameters();
    for (const auto& parameter : context.getParameters()) {
        auto it = targetParameters.find(parameter.first);
        if (it != targetParameters.end() && it->second != parameter.second)
            target.setParameter(parameter.first, parameter.second);
    }
}

void StaggeredDynamics::computeConservative(OpenMM::ContextImpl& context, int forceGroups) {
    if (!slowContext || numSubSteps == 1) {
        PairDynamics::computeConservative(context, forceGroups);
        return;
    }
    if (slowOmitsSoftForce) {
        SoftRepulsionKernel* soft = softForceToFuse(context, forceGroups);
        if (soft == nullptr) {
            // Its parameters changed so that the pairs no longer carry it: the main Context
            // evaluates every slow force (slower, not wrong).
            PairDynamics::computeConservative(context, forceGroups);
            return;
        }
        addSoftForceFromPairs(soft);
    }
    syncContext(context, *slowContext, slowBox);
    slowContext->setPositions(*platformData(context).positions);
    conservative = slowContext->getState(OpenMM::State::Forces, false, forceGroups).getForces();
}

void StaggeredDynamics::computeFastForce(OpenMM::ContextImpl& context, const StaggeredDPDIntegrator& integrator, long long step,
                                         std::vector<Vec3>& fast) {
    // K = 1 evaluates them in the full Context, as the base integrators do.
    if (fastContext && integrator.getNumSubSteps() > 1) {
        const std::vector<Vec3>& r = *platformData(context).positions;
        for (size_t k = 0; k < polymer.particles.size(); k++)
            fastPositions[k] = r[polymer.particles[k]];
        syncContext(context, *fastContext, fastBox);
        fastContext->setPositions(fastPositions);
        fast = fastContext->getState(OpenMM::State::Forces).getForces();
        checkFinite(fast, polymer.particles, false, "fast force", step);
        return;
    }
    context.calcForcesAndEnergy(true, false, integrator.getFastForceGroups());
    const std::vector<Vec3>& f = *platformData(context).forces;
    for (size_t k = 0; k < polymer.particles.size(); k++)
        fast[k] = f[polymer.particles[k]];
    checkFinite(fast, polymer.particles, false, "fast force", step);
    if (polymer.checkFastForceOutside)
        checkOutsidePolymer(f, polymer.index, step, name);
}

void StaggeredDynamics::computeInitialForce(OpenMM::ContextImpl& context, const StaggeredDPDIntegrator& integrator) {
    OpenMM::ReferencePlatform::PlatformData& data = platformData(context);
    const long long step = data.stepCount;
    if (baseScheme == StaggeredDPDIntegrator::VelocityVerlet)
        computeForceInOnePass(context, slowGroups(integrator), *data.velocities, step, integrator.getStepSize(), force);
    else {
        computeConservativeAndPairs(context, slowGroups(integrator), step);
        force = conservative;
    }
    computeFastForce(context, integrator, step, fastForce);
    setCarriedForceValid();
}

// Notation of algorithms.md section 6: s solvent, p polymer, Dt the outer step, dt = Dt/K
// the sub-step; `force` holds F, the slow force of the last outer step, `newForce` F^, the
// one of this step, and fastForce Fp (per polymer particle k of polymer[k]).
void StaggeredDynamics::step(OpenMM::ContextImpl& context, const StaggeredDPDIntegrator& integrator) {
    OpenMM::ReferencePlatform::PlatformData& data = platformData(context);
    const long long current = data.stepCount, next = current + 1;
    prepareStep(context, integrator);
    for (size_t k = 0; k < polymer.particles.size(); k++) {
        startPositions[k] = (*data.positions)[polymer.particles[k]];
        startVelocities[k] = (*data.velocities)[polymer.particles[k]];
    }
    context.getPeriodicBoxVectors(startBox[0], startBox[1], startBox[2]);
    predict(context, integrator, next);
    evaluatePredictedForce(context, integrator, next);
    kickSolvent(context, integrator);
    subCycle(context, integrator, next);
    force.swap(newForce);
    if (baseScheme == StaggeredDPDIntegrator::LoweAndersen)
        thermalise(context, integrator, current);
    finishStep(data, integrator.getStepSize());
}

void StaggeredDynamics::prepareStep(OpenMM::ContextImpl& context, const StaggeredDPDIntegrator& integrator) {
    if (integrator.getBaseScheme() != baseScheme)
        throw OpenMM::OpenMMException("StaggeredDPDIntegrator: the base scheme changed after the Context was created; call "
                                      "Context.reinitialize(True) after setBaseScheme()");
    OpenMM::ReferencePlatform::PlatformData& data = platformData(context);
    numSubSteps = integrator.getNumSubSteps();
    bool valid = carriedForceValid(*data.positions, *data.velocities);
    if (polymer.changed(integrator)) {
        updatePolymer(context.getSystem(), integrator);
        valid = false;
    }
    if (numSubSteps > 1 && !fastContextTried)
        makeSideContexts(context, integrator);
    if (!valid)
        computeInitialForce(context, integrator);
}

void StaggeredDynamics::makeSideContexts(OpenMM::ContextImpl& context, const StaggeredDPDIntegrator& integrator) {
    fastContextTried = true;
    // Only a cost: if a force cannot be copied (no serialization proxy, ...), the main
    // Context evaluates everything.
    try {
        makeFastContext(context, integrator);
    }
    catch (const OpenMM::OpenMMException&) {
        fastContext.reset();
        slowContext.reset();
    }
}

void StaggeredDynamics::predict(OpenMM::ContextImpl& context, const StaggeredDPDIntegrator& integrator, long long next) {
    const std::vector<Vec3>& v = *platformData(context).velocities;
    const std::vector<double>& invMass = thermostat.getParameters().getInverseMasses();
    const bool verlet = (baseScheme == StaggeredDPDIntegrator::VelocityVerlet);
    const double Dt = integrator.getStepSize(), lambda = integrator.getLambda(), mu = integrator.getMu(), a = integrator.getA();
    // Solvent: r += Dt u + Dt^2/(2m) F.  Polymer: r^ = r + Dt u + Dt^2/(2m) (F + Fp),
    // evaluated at r^^ = mu r + (1 - mu) r^.  Velocity-Verlet base: the predicted velocities
    // u^ = u + lambda Dt F/m (solvent), u^^ = a u + (1 - a) (u + lambda Dt (F + Fp)/m) (polymer).
    // Under shear they take the jumps of the molecules that cross, as the positions do: F^'s
    // dissipative force pairs them with the wrapped positions.
    movePositions(context, next, Dt, [&](size_t i) {
        const int k = polymer.index[i];
        Vec3 f = force[i];
        if (k >= 0)
            f += fastForce[k];
        if (verlet) {
            predicted[i] = v[i] + f * (lambda * Dt * invMass[i]);
            if (k >= 0)
                predicted[i] = v[i] * a + predicted[i] * (1 - a);
        }
        const Vec3 move = v[i] * Dt + f * (0.5 * Dt * Dt * invMass[i]);
        return (k >= 0 ? move * (1 - mu) : move);
    }, verlet ? &predicted : nullptr);
}

void StaggeredDynamics::evaluatePredictedForce(OpenMM::ContextImpl& context, const StaggeredDPDIntegrator& integrator,
                                               long long next) {
    // F^: the one slow evaluation (and pair search) of the outer step.
    if (baseScheme == StaggeredDPDIntegrator::VelocityVerlet)
        computeForceInOnePass(context, slowGroups(integrator), predicted, next, integrator.getStepSize(), newForce);
    else {
        computeConservativeAndPairs(context, slowGroups(integrator), next);
        newForce = conservative;
    }
}

void StaggeredDynamics::kickSolvent(OpenMM::ContextImpl& context, const StaggeredDPDIntegrator& integrator) {
    std::vector<Vec3>& v = *platformData(context).velocities;
    const std::vector<double>& invMass = thermostat.getParameters().getInverseMasses();
    const double Dt = integrator.getStepSize();
    // Solvent: u += Dt/(2m) (F + F^).
    forEachParticle(v.size(), [&](size_t i) {
        if (polymer.index[i] < 0)
            v[i] += (force[i] + newForce[i]) * (0.5 * Dt * invMass[i]);
    });
}

void StaggeredDynamics::subCycle(OpenMM::ContextImpl& context, const StaggeredDPDIntegrator& integrator, long long next) {
    std::vector<Vec3>& r = *platformData(context).positions;
    std::vector<Vec3>& v = *platformData(context).velocities;
    const double b = integrator.getB();
    // Under shear the predicting drift slid the box to the end of the step and wrapped the
    // molecules that crossed, the polymer's too, with their velocity jumps.  The polymer
    // starts again from the start of the step, so from that time's box and velocities too;
    // each sub-step slides the box on and wraps the polymer when it crosses.
    Vec3 endBox[3];
    context.getPeriodicBoxVectors(endBox[0], endBox[1], endBox[2]);
    const bool sheared = (thermostat.getParameters().getShearRate() != 0);
    if (sheared)
        context.setPeriodicBoxVectors(startBox[0], startBox[1], startBox[2]);
    // Polymer: K sub-steps from the start of the outer step, driven by F^^ = b F + (1 - b) F^
    // and the fast force, which alone is re-evaluated.
    for (size_t k = 0; k < polymer.particles.size(); k++) {
        const int p = polymer.particles[k];
        r[p] = startPositions[k];
        v[p] = startVelocities[k];
        drivingForce[k] = force[p] * b + newForce[p] * (1 - b);
    }
    for (int s = 0; s < integrator.getNumSubSteps(); s++)
        subStep(context, integrator, s, next);
    // K sub-step slides make U Dt up to rounding: the step ends in the box F^ was evaluated in.
    if (sheared)
        context.setPeriodicBoxVectors(endBox[0], endBox[1], endBox[2]);
}

void StaggeredDynamics::subStep(OpenMM::ContextImpl& context, const StaggeredDPDIntegrator& integrator, int s, long long next) {
    OpenMM::ReferencePlatform::PlatformData& data = platformData(context);
    std::vector<Vec3>& v = *data.velocities;
    const std::vector<double>& invMass = thermostat.getParameters().getInverseMasses();
    const int K = integrator.getNumSubSteps();
    const double dt = integrator.getStepSize() / K;
    moveParticles(polymer.particles, *data.positions, next, [&](size_t k) {
        const int p = polymer.particles[k];
        return v[p] * dt + (drivingForce[k] + fastForce[k]) * (0.5 * dt * dt * invMass[p]);
    });
    // The solvent is inside the box already: only polymer molecules can cross here.
    shear.slide(context, thermostat.getParameters().getShearRate(), dt, *data.positions, v);
    computeFastForce(context, integrator, next, newFastForce);
    // The slow force at the ends of the sub-step: linear in time from F to F^ (weighted), or
    // F and F^ (non-weighted).
    const bool weighted = integrator.getWeighted();
    const double oldF = (weighted ? (double) (K - s) / K : 1.0), oldNew = (weighted ? (double) s / K : 0.0);
    const double newF = (weighted ? (double) (K - s - 1) / K : 0.0), newNew = (weighted ? (double) (s + 1) / K : 1.0);
    for (size_t k = 0; k < polymer.particles.size(); k++) {
        const int p = polymer.particles[k];
        const Vec3 slowOld = force[p] * oldF + newForce[p] * oldNew;
        const Vec3 slowNew = force[p] * newF + newForce[p] * newNew;
        v[p] += ((slowOld + fastForce[k]) + (slowNew + newFastForce[k])) * (0.5 * dt * invMass[p]);
        fastForce[k] = newFastForce[k];
    }
}

// Lowe base: the pair thermalisation, once per outer step, over the pairs at the end-of-step
// positions.  Paper 002 Table 2 thermalises, after the sub-cycle, "N_p distinct pairs i, j
// such that r_ij < r_c" (section 4.2: "The thermalization is done once at the end of the Dt
// cycle"), with the unhatted r_ij: the corrected positions, not the provisional r^^_p at which
// F^ was evaluated ("we use provisional values not only for the velocity of the solvent and
// the polymer, but also the position of the polymer ... The velocity and the position of the
// polymer are corrected in the subsequent loop", section 4.1).  With K > 1, or b != 1, the
// polymer is no longer at r^^_p: the pairs found there would miss the polymer pairs that came
// into range and give the others stale directions.  So the pairs are searched again here:
// one more pair search per outer step, for this base only.
void StaggeredDynamics::thermalise(OpenMM::ContextImpl& context, const StaggeredDPDIntegrator& integrator, long long current) {
    OpenMM::ReferencePlatform::PlatformData& data = platformData(context);
    const DPDPairParameters& parameters = thermostat.getParameters();
    Vec3 box[3];
    context.getPeriodicBoxVectors(box[0], box[1], box[2]);
    thermostat.updatePairs(*data.positions, box);
    pairSweep.prepare(thermostat);
    pairSweep.run(thermostat, *data.velocities,
                  LowePairUpdate<>{thermostat.getRandom(), current, integrator.getStepSize(), parameters.getKT(),
                                   {parameters.getInverseMasses()}},
                  false);
}

// After the shared part (seed, validity, slow force): the fast force on each polymer particle.
void StaggeredDynamics::saveExtraState(std::ostream& stream) const {
    putVectors(stream, fastForce);
}

void StaggeredDynamics::loadExtraState(CheckpointReader& reader) {
    loadedFastForce.resize(fastForce.size());
    reader.takeVectors(loadedFastForce, "the fast force on the polymer particles");
}
