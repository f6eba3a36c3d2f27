#include "openmmdpd/CommonStaggeredDynamics.h"
#include "CommonDPDKernelSources.h"
#include "openmmdpd/CheckpointIO.h"
#include "openmmdpd/StaggeredSteps.h"
#include "openmmdpd/StepState.h"
#include "openmm/common/ContextSelector.h"

using namespace DPDPlugin;
using namespace OpenMM;

CommonStaggeredDynamics::CommonStaggeredDynamics(ComputeContext& cc, const System& system, const StaggeredDPDIntegrator& integrator,
                                                 const std::string& platform) :
        CommonSweepDynamics(cc, system, integrator, platform, {CommonDPDKernelSources::staggered},
                            integrator.getBaseScheme() == StaggeredDPDIntegrator::VelocityVerlet),
        baseScheme(integrator.getBaseScheme()) {
    ContextSelector selector(cc);
    ArrayInterface& posqCorrection = cc.getUseMixedPrecision() ? cc.getPosqCorrection() : cc.getPosq();
    const int n = numAtoms(), size = std::max(n, 1), mixed4Size = mixedIsDouble(cc) ? 4 * sizeof(double) : 4 * sizeof(float);
    polymerFlag.initialize<int>(cc, size, "dpdPolymer");
    for (ComputeArray* force : {&newSlow, &fast, &newFast}) {
        force->initialize<long long>(cc, 3 * size, "dpdStaggeredForce");
        force->upload(std::vector<long long>(3 * size, 0));
    }
    startPosition.initialize(cc, size, mixed4Size, "dpdStartPosition");
    startVelocity.initialize(cc, size, mixed4Size, "dpdStartVelocity");
    // The scalars, and the output of takeForceKernel, are set where they are used.
    takeForceKernel = program->createKernel("staggeredTakeForce");
    takeForceKernel->addArg(n);
    takeForceKernel->addArg(cc.getPaddedNumAtoms());
    addArrayArgs(takeForceKernel, {&cc.getAtomIndexArray(), &cc.getLongForceBuffer(), &polymerFlag});
    takeForceKernel->addArg();
    takeForceKernel->addArg();
    predictKernel = program->createKernel("staggeredPredict");
    predictKernel->addArg(n);
    addArrayArgs(predictKernel, {&cc.getPosq(), &posqCorrection, &cc.getVelm(), &cc.getAtomIndexArray(), &polymerFlag, &carriedForce,
                                 &fast, &velocity, &startPosition, &startVelocity});
    for (int k = 0; k < 5; k++)
        predictKernel->addArg();
    addArrayArgs(predictKernel, {&status, &moveValue});
    kickSolventKernel = program->createKernel("staggeredKickSolvent");
    kickSolventKernel->addArg(n);
    addArrayArgs(kickSolventKernel, {&cc.getVelm(), &cc.getAtomIndexArray(), &polymerFlag, &carriedForce, &newSlow});
    kickSolventKernel->addArg();
    kickSolventKernel->addArg();
    kickSolventKernel->addArg(status);
    restoreKernel = program->createKernel("staggeredRestorePolymer");
    restoreKernel->addArg(n);
    addArrayArgs(restoreKernel, {&cc.getPosq(), &posqCorrection, &cc.getVelm(), &cc.getAtomIndexArray(), &polymerFlag, &startPosition,
                                 &startVelocity});
    driftKernel = program->createKernel("staggeredSubStepDrift");
    driftKernel->addArg(n);
    addArrayArgs(driftKernel, {&cc.getPosq(), &posqCorrection, &cc.getVelm(), &cc.getAtomIndexArray(), &polymerFlag, &carriedForce,
                               &newSlow, &fast});
    for (int k = 0; k < 3; k++)
        driftKernel->addArg();
    addArrayArgs(driftKernel, {&status, &moveValue});
    kickKernel = program->createKernel("staggeredSubStepKick");
    kickKernel->addArg(n);
    addArrayArgs(kickKernel, {&cc.getVelm(), &cc.getAtomIndexArray(), &polymerFlag, &carriedForce, &newSlow, &fast, &newFast});
    for (int k = 0; k < 3; k++)
        kickKernel->addArg();
    kickKernel->addArg(status);
    updatePolymer(system, integrator);
}

void CommonStaggeredDynamics::updatePolymer(const System& system, const StaggeredDPDIntegrator& integrator) {
    polymer.select(system, integrator);
    std::vector<int> flags(std::max(numAtoms(), 1), 0);
    for (int p : polymer.particles)
        flags[p] = 1;
    polymerFlag.upload(flags);
}

void CommonStaggeredDynamics::step(ContextImpl& context, const StaggeredDPDIntegrator& integrator) {
    ContextSelector selector(cc);
    requireBaseScheme(integrator, baseScheme);
    const double Dt = integrator.getStepSize();
    const long long current = cc.getStepCount(), next = current + 1;
    bool valid = carriedIsValid(context);
    if (polymer.changed(integrator)) {
        updatePolymer(context.getSystem(), integrator);
        valid = false;
    }
    if (!valid) {
        gatherVelocities();
        slowForce(context, integrator, current, carriedForce);
        fastForce(context, integrator, current, fast);
        carried.setValid();
    }
    Vec3 startBox[3];
    cc.getPeriodicBoxVectors(startBox[0], startBox[1], startBox[2]);
    predict(integrator);
    // F^ = F(r_s, r^^_p ; u^_s, u^^_p): the one slow evaluation of the outer step.
    slowForce(context, integrator, next, newSlow);
    setMixedArg(cc, kickSolventKernel, 6, Dt);
    setMixedArg(cc, kickSolventKernel, 7, velocityBound());
    kickSolventKernel->execute(numAtoms());
    subCycle(context, integrator, startBox, next);
    newSlow.copyTo(carriedForce);
    // Lowe's thermalisation once per outer step, over the pairs at the end-of-step positions.
    if (baseScheme == StaggeredDPDIntegrator::LoweAndersen)
        sweep(LoweRule, Dt, Dt, PairRandom::PairThermalisation, PairRandom::TransverseNoise, current, false);
    checkStatus(context, next);
    finishStep(Dt);
}

void CommonStaggeredDynamics::slowForce(ContextImpl& context, const StaggeredDPDIntegrator& integrator, long long step,
                                        ComputeArray& out) {
    conservativeForce(context, integrator.getIntegrationForceGroups() & ~integrator.getFastForceGroups());
    if (baseScheme == StaggeredDPDIntegrator::VelocityVerlet) {
        pairForces(step, integrator.getStepSize(), 3);
        sumForcesInto(out, true);
        return;
    }
    takeForceKernel->setArg(5, 0);
    takeForceKernel->setArg(6, out);
    takeForceKernel->execute(numAtoms());
}

void CommonStaggeredDynamics::fastForce(ContextImpl& context, const StaggeredDPDIntegrator& integrator, long long step,
                                        ComputeArray& out) {
    conservativeForce(context, integrator.getFastForceGroups());
    if (polymer.checkFastForceOutside) {
        std::vector<Vec3> forces;
        context.getForces(forces);
        checkOutsidePolymer(forces, polymer.index, step, name);
    }
    takeForceKernel->setArg(5, 1);
    takeForceKernel->setArg(6, out);
    takeForceKernel->execute(numAtoms());
}

void CommonStaggeredDynamics::predict(const StaggeredDPDIntegrator& integrator) {
    const double Dt = integrator.getStepSize();
    setMixedArg(cc, predictKernel, 11, Dt);
    setMixedArg(cc, predictKernel, 12, integrator.getLambda());
    setMixedArg(cc, predictKernel, 13, integrator.getMu());
    setMixedArg(cc, predictKernel, 14, integrator.getA());
    setMixedArg(cc, predictKernel, 15, maxMove2());
    predictKernel->execute(numAtoms());
    // Under shear the predicted velocities take the jumps of the molecules that cross, as
    // their positions do: F^'s dissipative force pairs them with the wrapped positions.
    finishDrift(Dt, true);
}

void CommonStaggeredDynamics::subCycle(ContextImpl& context, const StaggeredDPDIntegrator& integrator, const Vec3* startBox,
                                       long long next) {
    // Under shear the predicting drift slid the box to the end of the step; the polymer
    // starts again from the start of the step, in that time's box, and each sub-step slides
    // it on.  K sub-step slides make U Dt up to rounding: the step ends in F^'s box.
    Vec3 endBox[3];
    cc.getPeriodicBoxVectors(endBox[0], endBox[1], endBox[2]);
    const bool sheared = (parameters.getShearRate() != 0);
    if (sheared)
        cc.setPeriodicBoxVectors(startBox[0], startBox[1], startBox[2]);
    restoreKernel->execute(numAtoms());
    for (int s = 0; s < integrator.getNumSubSteps(); s++)
        subStep(context, integrator, s, next);
    if (sheared)
        cc.setPeriodicBoxVectors(endBox[0], endBox[1], endBox[2]);
}

void CommonStaggeredDynamics::subStep(ContextImpl& context, const StaggeredDPDIntegrator& integrator, int s, long long next) {
    const int K = integrator.getNumSubSteps();
    const double dt = integrator.getStepSize() / K;
    setMixedArg(cc, driftKernel, 9, dt);
    setMixedArg(cc, driftKernel, 10, integrator.getB());
    setMixedArg(cc, driftKernel, 11, maxMove2());
    driftKernel->execute(numAtoms());
    finishDrift(dt, false);
    fastForce(context, integrator, next, newFast);
    // The slow force at the sub-step's two ends, linear in time from F to F^ (weighted), or F and F^.
    const SubStepWeights w(integrator, s);
    const double weights[4] = {w.oldOfF, w.oldOfNewF, w.newOfF, w.newOfNewF};
    setMixedArg(cc, kickKernel, 8, dt);
    setMixed4Arg(cc, kickKernel, 9, weights);
    setMixedArg(cc, kickKernel, 10, velocityBound());
    kickKernel->execute(numAtoms());
}

// The Reference's layout: the number of polymer particles, then Fp on each.
void CommonStaggeredDynamics::saveExtraState(std::ostream& stream) const {
    std::vector<long long> fixed;
    const_cast<ComputeArray&>(fast).download(fixed);
    const int n = numAtoms();
    std::vector<Vec3> values(polymer.particles.size());
    for (size_t k = 0; k < values.size(); k++)
        for (int d = 0; d < 3; d++)
            values[k][d] = fromFixedForce(fixed[polymer.particles[k] + d * n]);
    putVectors(stream, values);
}

void CommonStaggeredDynamics::loadExtraState(CheckpointReader& reader) {
    loadedFast.resize(polymer.particles.size());
    reader.takeVectors(loadedFast, "the fast force on the polymer particles");
}

void CommonStaggeredDynamics::commitExtraState() {
    const int n = numAtoms();
    std::vector<long long> fixed(3 * std::max(n, 1), 0);
    for (size_t k = 0; k < loadedFast.size(); k++)
        for (int d = 0; d < 3; d++)
            fixed[polymer.particles[k] + d * n] = toFixedForce(loadedFast[k][d]);
    fast.upload(fixed);
    loadedFast.clear();
}
