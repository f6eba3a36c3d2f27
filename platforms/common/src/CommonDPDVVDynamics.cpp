#include "openmmdpd/CommonDPDVVDynamics.h"
#include "CommonDPDKernelSources.h"
#include "openmm/common/ContextSelector.h"
#include "openmm/common/IntegrationUtilities.h"
#include <cmath>

using namespace DPDPlugin;
using namespace OpenMM;

CommonDPDVVDynamics::CommonDPDVVDynamics(ComputeContext& cc, const System& system, const DPDVVIntegrator& integrator,
                                         const std::string& platform) :
        CommonDynamics(cc, system, integrator, platform, {CommonDPDKernelSources::dpdvv}, true) {
    ContextSelector selector(cc);
    ArrayInterface& posqCorrection = cc.getUseMixedPrecision() ? cc.getPosqCorrection() : cc.getPosq();
    const int n = numAtoms();
    // The scalars (dt, lambda, bounds) are left empty here and set every step.
    grootWarren1 = program->createKernel("grootWarrenPart1");
    grootWarren1->addArg(n);
    addArrayArgs(grootWarren1, {&cc.getPosq(), &posqCorrection, &cc.getVelm(), &cc.getAtomIndexArray(), &carriedForce, &velocity});
    grootWarren1->addArg();
    grootWarren1->addArg();
    grootWarren1->addArg();
    grootWarren1->addArg(status);
    grootWarren1->addArg(moveValue);
    addDriftArgs(grootWarren1);
    grootWarren2 = program->createKernel("grootWarrenPart2");
    grootWarren2->addArg(n);
    grootWarren2->addArg(cc.getPaddedNumAtoms());
    addArrayArgs(grootWarren2, {&cc.getVelm(), &cc.getAtomIndexArray(), &cc.getLongForceBuffer(), &fd, &fr, &carriedForce});
    grootWarren2->addArg();
    grootWarren2->addArg();
    grootWarren2->addArg(status);
    dpdvv1 = program->createKernel("dpdvvPart1");
    dpdvv1->addArg(n);
    addArrayArgs(dpdvv1, {&cc.getPosq(), &posqCorrection, &cc.getVelm(), &cc.getAtomIndexArray(), &carriedForce, &velocity});
    dpdvv1->addArg();
    dpdvv1->addArg();
    dpdvv1->addArg(status);
    dpdvv1->addArg(moveValue);
    addDriftArgs(dpdvv1);
    noDissipative.initialize(cc, std::max(n, 1), mixedIsDouble(cc) ? 4 * sizeof(double) : 4 * sizeof(float), "dpdNoDissipative");
    dpdvv2 = program->createKernel("dpdvvPart2");
    dpdvv2->addArg(n);
    addArrayArgs(dpdvv2, {&cc.getVelm(), &cc.getAtomIndexArray(), &carriedForce, &noDissipative});
    dpdvv2->addArg();
    dissipativeKick = program->createKernel("dpdvvDissipativeKick");
    dissipativeKick->addArg(n);
    addArrayArgs(dissipativeKick, {&cc.getVelm(), &cc.getAtomIndexArray(), &noDissipative, &fd, &velocity});
    dissipativeKick->addArg();
    dpdvv3 = program->createKernel("dpdvvPart3");
    dpdvv3->addArg(n);
    addArrayArgs(dpdvv3, {&cc.getVelm(), &cc.getAtomIndexArray(), &fd, &carriedForce});
    dpdvv3->addArg();
    dpdvv3->addArg(status);
}

void CommonDPDVVDynamics::step(ContextImpl& context, const DPDVVIntegrator& integrator) {
    ContextSelector selector(cc);
    const double dt = integrator.getStepSize();
    if (!carriedIsValid(context)) {
        gatherVelocities();
        conservativeForce(context, integrator.getIntegrationForceGroups());
        pairForces(cc.getStepCount(), dt, 3);
        sumIntoCarried(true);
        carried.setValid();
    }
    const long long next = cc.getStepCount() + 1;
    startThermostatVirial();
    if (integrator.getVariant() == DPDVVIntegrator::GrootWarren)
        grootWarrenStep(context, integrator, next);
    else
        dpdvvStep(context, integrator, next);
    checkStatus(context, next);
    finishThermostatVirial();
    finishStep(dt);
}

void CommonDPDVVDynamics::grootWarrenStep(ContextImpl& context, const DPDVVIntegrator& integrator, long long next) {
    const double dt = integrator.getStepSize();
    // r += dt v + dt^2/(2m) F;  v~ = v + lambda dt F/m
    setMixedArg(cc, grootWarren1, 7, dt);
    setMixedArg(cc, grootWarren1, 8, integrator.getLambda());
    setMixedArg(cc, grootWarren1, 9, maxMove2());
    grootWarren1->execute(numAtoms());
    constrainDrift(dt, integrator.getConstraintTolerance());  // v and the predicted velocity take the corrections
    finishDrift(dt, true);  // and the jumps
    // F' = FC(r) + FD(r, v~) + FR(r);  v += dt/(2m) (F + F')
    conservativeForce(context, integrator.getIntegrationForceGroups());
    pairForces(next, dt, 3, true, 3);
    setMixedArg(cc, grootWarren2, 8, dt);
    setMixedArg(cc, grootWarren2, 9, velocityBound());
    grootWarren2->execute(numAtoms());
    constrainVelocities(integrator.getConstraintTolerance());
}

void CommonDPDVVDynamics::dpdvvStep(ContextImpl& context, const DPDVVIntegrator& integrator, long long next) {
    const double dt = integrator.getStepSize();
    // (1) v += dt/(2m) F;  (2) r += dt v
    setMixedArg(cc, dpdvv1, 7, dt);
    setMixedArg(cc, dpdvv1, 8, maxMove2());
    dpdvv1->execute(numAtoms());
    constrainDrift(dt, integrator.getConstraintTolerance());
    finishDrift(dt, true);  // velm and its copy by atom
    // (3) FC(r), FD(r, v), FR(r);  (4a) v° <- v + dt/(2m) (FC + FR).  The step's thermostat
    // virial: FR's, and that of the FD carried into the next step.
    conservativeForce(context, integrator.getIntegrationForceGroups());
    pairForces(next, dt, 3, true, 2);
    sumIntoCarried(false);
    setMixedArg(cc, dpdvv2, 5, dt);
    dpdvv2->execute(numAtoms());
    dissipativeIterations(integrator, next);
    setMixedArg(cc, dpdvv3, 5, velocityBound());
    dpdvv3->execute(numAtoms());
}

void CommonDPDVVDynamics::dissipativeIterations(const DPDVVIntegrator& integrator, long long next) {
    // (4b) v <- v° + dt/(2m) FD ; (5) FD <- FD(r, v), until the kinetic energy changes by
    // less than the tolerance (relative), at most maxIterations times, for SC-VV.
    const double dt = integrator.getStepSize();
    const bool selfConsistent = (integrator.getVariant() == DPDVVIntegrator::SelfConsistent);
    const int iterations = selfConsistent ? integrator.getMaxIterations() : 1;
    setMixedArg(cc, dissipativeKick, 6, dt);
    double previousKinetic = 0;
    for (int it = 0; it < iterations; it++) {
        dissipativeKick->execute(numAtoms());
        constrainVelocities(integrator.getConstraintTolerance());
        pairForces(next, dt, 1, false, selfConsistent ? 0 : 1);
        if (!selfConsistent)
            return;
        const double kinetic = cc.getIntegrationUtilities().computeKineticEnergy(0);
        if (it > 0 && std::fabs(kinetic - previousKinetic) <= integrator.getTolerance() * kinetic)
            break;
        previousKinetic = kinetic;
    }
    // Only the last FD is carried into the next step: its virial, once more.
    if (thermostatVirial != nullptr)
        pairForces(next, dt, 1, false, 1);
}
