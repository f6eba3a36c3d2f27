#include "openmmdpd/CommonDenOtterClarkeDynamics.h"
#include "CommonDPDKernelSources.h"
#include "openmm/common/ContextSelector.h"

using namespace DPDPlugin;
using namespace OpenMM;

CommonDenOtterClarkeDynamics::CommonDenOtterClarkeDynamics(ComputeContext& cc, const System& system,
                                                           const DenOtterClarkeIntegrator& integrator, const std::string& platform) :
        CommonDynamics(cc, system, integrator, platform, {CommonDPDKernelSources::dpdvv, CommonDPDKernelSources::denOtterClarke}, true),
        thermostatMass(DenOtterClarkeSums::thermostatMass(parameters)) {
    ContextSelector selector(cc);
    ArrayInterface& posqCorrection = cc.getUseMixedPrecision() ? cc.getPosqCorrection() : cc.getPosq();
    const int n = numAtoms();
    for (int i = 0; i < n; i++)
        activeAtoms += (parameters.getActive()[i] ? 1 : 0);
    termThreads = std::max(1, std::min(n, cc.getNumThreadBlocks() * ComputeContext::ThreadBlockSize));
    termRows.initialize(cc, 3 * termThreads, mixedIsDouble(cc) ? sizeof(double) : sizeof(float), "dpdOtterClarkeTerms");
    termsKernel = program->createKernel("denOtterClarkeTerms");
    termsKernel->addArg(n);
    termsKernel->addArg(termThreads);
    addArrayArgs(termsKernel, {&cc.getVelm(), &cc.getAtomIndexArray(), &fd, &fr});
    termsKernel->addArg();  // dt: set per step
    termsKernel->addArg(termRows);
    stepKernel = program->createKernel("denOtterClarkeStep");
    stepKernel->addArg(n);
    stepKernel->addArg(cc.getPaddedNumAtoms());
    addArrayArgs(stepKernel, {&cc.getPosq(), &posqCorrection, &cc.getVelm(), &cc.getAtomIndexArray(), &cc.getLongForceBuffer(), &fd, &fr});
    for (int k = 0; k < 5; k++)
        stepKernel->addArg();  // dt, alpha, beta and the bounds: set per step
    stepKernel->addArg(status);
    stepKernel->addArg(moveValue);
    addDriftArgs(stepKernel);
}

void CommonDenOtterClarkeDynamics::step(ContextImpl& context, const DenOtterClarkeIntegrator& integrator) {
    ContextSelector selector(cc);
    const double dt = integrator.getStepSize();
    const long long now = cc.getStepCount();
    // (3) of the step before: FC(r), FD(r, v), FR(r), the random numbers keyed by this step
    gatherVelocities();
    conservativeForce(context, integrator.getIntegrationForceGroups());
    pairForces(now, dt, 3);
    measure(dt);
    double alpha, beta;
    integrator.getPrefactors(thermostatMass, alpha, beta);
    // (1) v += alpha dt/m (FC + FD) + beta dt/m FR ; (2) r += dt v
    setMixedArg(cc, stepKernel, 9, dt);
    setMixedArg(cc, stepKernel, 10, alpha);
    setMixedArg(cc, stepKernel, 11, beta);
    setMixedArg(cc, stepKernel, 12, maxMove2());
    setMixedArg(cc, stepKernel, 13, velocityBound());
    stepKernel->execute(numAtoms());
    constrainDrift(dt, integrator.getConstraintTolerance());
    finishDrift(dt, false);
    // The next step's FD sees only velocities the constraints allow, as on the Reference.
    constrainVelocities(integrator.getConstraintTolerance());
    checkStatus(context, now + 1);
    finishStep(dt);
}

void CommonDenOtterClarkeDynamics::measure(double dt) {
    setMixedArg(cc, termsKernel, 6, dt);
    termsKernel->execute(termThreads);
    const std::vector<double> rows = downloadMixed(cc, termRows);
    DenOtterClarkeSums terms;
    for (int k = 0; k < termThreads; k++) {
        terms.fdDotV += rows[k];
        terms.fdDotFD += rows[k + termThreads];
        terms.frDotFR += rows[k + 2 * termThreads];
    }
    terms.count = activeAtoms;
    sums.add(terms);
}
