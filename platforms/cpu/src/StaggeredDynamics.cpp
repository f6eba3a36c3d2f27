#include "openmmdpd/CheckpointIO.h"
#include "openmmdpd/StaggeredDynamics.h"
#include "openmmdpd/StaggeredSteps.h"
#include "openmmdpd/PairEvaluators.h"
#include "openmmdpd/DPDSoftRepulsionForce.h"
#include "openmmdpd/MDPDForce.h"
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
    for (auto* v : {&fastForce, &newFastForce, &startPositions, &startVelocities, &drivingForce})
        v->assign(polymer.particles.size(), Vec3());
    fastForces.reset();
    slowContext.reset();
    slowIntegrator.reset();
    slowSystem.reset();
    fastContextTried = false;
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

/** Whether a thermostat pass can add this kind of force (PairDynamics::pairForceToFuse). */
bool isFusable(const OpenMM::Force& force) {
    return dynamic_cast<const DPDSoftRepulsionForce*>(&force) != nullptr || dynamic_cast<const MDPDForce*>(&force) != nullptr;
}

} // namespace

void StaggeredDynamics::makeSlowContext(OpenMM::ContextImpl& context, const StaggeredDPDIntegrator& integrator) {
    std::unique_ptr<OpenMM::System> system(OpenMM::XmlSerializer::clone<OpenMM::System>(context.getSystem()));
    // A fused force that the thermostat pairs can carry is added from them (as at K = 1), not
    // searched again here.
    slowOmitsFusedForce = (pairForceToFuse(context, slowGroups(integrator)) != nullptr);
    for (int f = system->getNumForces() - 1; f >= 0; f--)
        if ((integrator.getFastForceGroups() & (1 << system->getForce(f).getForceGroup())) != 0 ||
            (slowOmitsFusedForce && isFusable(system->getForce(f))))
            system->removeForce(f);
    slowContext.reset();
    if (system->getNumForces() == 0)
        return;  // nothing left for it: the main Context's path skips the evaluation
    slowSystem = std::move(system);
    slowIntegrator.reset(new OpenMM::VerletIntegrator(1.0));
    slowContext.reset(new OpenMM::Context(*slowSystem, *slowIntegrator, context.getPlatform(), contextProperties(context)));
    slowContext->getState(0).getPeriodicBoxVectors(slowBox[0], slowBox[1], slowBox[2]);
}

void StaggeredDynamics::computeConservative(OpenMM::ContextImpl& context, int forceGroups) {
    if (!slowContext || numSubSteps == 1) {
        PairDynamics::computeConservative(context, forceGroups);
        return;
    }
    if (slowOmitsFusedForce) {
        FusedPairForce* fused = pairForceToFuse(context, forceGroups);
        if (fused == nullptr) {
            // Its parameters changed so that the pairs no longer carry it: the main Context
            // evaluates every slow force (slower, not wrong).
            PairDynamics::computeConservative(context, forceGroups);
            return;
        }
        addForceFromPairs(context, fused);
    }
    Vec3 box[3];
    context.getPeriodicBoxVectors(box[0], box[1], box[2]);
    syncBoxAndParameters(*slowContext, box, context.getParameters(), slowBox);
    slowContext->setPositions(*platformData(context).positions);
    conservative = slowContext->getState(OpenMM::State::Forces, false, forceGroups).getForces();
}

void StaggeredDynamics::computeFastForce(OpenMM::ContextImpl& context, const StaggeredDPDIntegrator& integrator, long long step,
                                         std::vector<Vec3>& fast) {
    // K = 1 evaluates them in the full Context, as the base integrators do.
    if (fastForces && integrator.getNumSubSteps() > 1) {
        Vec3 box[3];
        context.getPeriodicBoxVectors(box[0], box[1], box[2]);
        fastForces->compute(*platformData(context).positions, box, context.getParameters(), fast);
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

// Notation of docs/theory/staggered.md: s solvent, p polymer, Dt the outer step, dt = Dt/K
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
    requireBaseScheme(integrator, baseScheme);
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
        fastForces = PolymerForceContext::create(context.getSystem(), integrator.getFastForceGroups(), polymer,
                                                 context.getPlatform(), contextProperties(context));
        if (fastForces)
            makeSlowContext(context, integrator);
    }
    catch (const OpenMM::OpenMMException&) {
        fastForces.reset();
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
    const SubStepWeights w(integrator, s);
    for (size_t k = 0; k < polymer.particles.size(); k++) {
        const int p = polymer.particles[k];
        const Vec3 slowOld = force[p] * w.oldOfF + newForce[p] * w.oldOfNewF;
        const Vec3 slowNew = force[p] * w.newOfF + newForce[p] * w.newOfNewF;
        v[p] += ((slowOld + fastForce[k]) + (slowNew + newFastForce[k])) * (0.5 * dt * invMass[p]);
        fastForce[k] = newFastForce[k];
    }
}

// Lowe base: the pair thermalisation, once per outer step, over the pairs at the end-of-step
// positions.  Symeonidis and Karniadakis 2006, Table 2, thermalises, after the sub-cycle,
// "N_p distinct pairs i, j such that r_ij < r_c" (section 4.2: "The thermalization is done once at the end of the Dt
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
    thermostat.drawBits(PairRandom::PairThermalisation, current, pairBits);
    pairSweep.run(thermostat, *data.velocities,
                  LowePairUpdate<>{integrator.getStepSize(), parameters.getKT(), {parameters.getInverseMasses()}}, pairBits, false);
}

// After the shared part (seed, validity, slow force): the fast force on each polymer particle.
void StaggeredDynamics::saveExtraState(std::ostream& stream) const {
    putVectors(stream, fastForce);
}

void StaggeredDynamics::loadExtraState(CheckpointReader& reader) {
    loadedFastForce.resize(fastForce.size());
    reader.takeVectors(loadedFastForce, "the fast force on the polymer particles");
}
