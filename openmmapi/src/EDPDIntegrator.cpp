#include "openmmdpd/EDPDIntegrator.h"
#include "openmmdpd/DPDKernels.h"
#include "openmmdpd/internal/ParameterChecks.h"
#include <cmath>

using namespace DPDPlugin;

EDPDIntegrator::EDPDIntegrator(double temperature, double defaultFriction, double defaultCutoff, double alpha, double stepSize) :
        DPDThermostatIntegrator("EDPDIntegrator", temperature, defaultFriction, defaultCutoff, stepSize), alpha(1),
        scheme(OneSided) {
    setAlpha(alpha);
}

void EDPDIntegrator::setAlpha(double a) {
    require(std::isfinite(a) && a > 0, "EDPDIntegrator: alpha must be > 0 /ps, got " + numberText(a));
    alpha = a;
}

void EDPDIntegrator::setScheme(Scheme s) {
    require(s == OneSided || s == Symmetric,
            "EDPDIntegrator: scheme must be OneSided (0) or Symmetric (1), got " + std::to_string((int) s));
    scheme = s;
}

void EDPDIntegrator::validate(const OpenMM::System& system) const {
    DPDThermostatIntegrator::validate(system);
    require(hasStandardWeights(), "EDPDIntegrator: the weight exponents must be 2 (defaultWeightExponent and every type "
            "pair's): extended DPD's pair variables are coupled through w = 1 - r/rc");
}

double EDPDIntegrator::getPairVariable(int particle1, int particle2) const {
    double value;
    long long step;
    if (!getStepKernel().getAs<const IntegrateEDPDStepKernel>().getPairVariable(particle1, particle2, value, step))
        return NAN;
    return value;
}

long long EDPDIntegrator::getPairVariableStep(int particle1, int particle2) const {
    double value;
    long long step;
    if (!getStepKernel().getAs<const IntegrateEDPDStepKernel>().getPairVariable(particle1, particle2, value, step))
        return -1;
    return step;
}

long long EDPDIntegrator::getNumPairVariables() const {
    return getStepKernel().getAs<const IntegrateEDPDStepKernel>().getNumPairVariables();
}

std::string EDPDIntegrator::kernelName() const {
    return IntegrateEDPDStepKernel::Name();
}

void EDPDIntegrator::initializeStepKernel(OpenMM::Kernel& kernel, const OpenMM::System& system) const {
    kernel.getAs<IntegrateEDPDStepKernel>().initialize(system, *this);
}

void EDPDIntegrator::executeStepKernel(OpenMM::Kernel& kernel, OpenMM::ContextImpl& context) const {
    kernel.getAs<IntegrateEDPDStepKernel>().execute(context, *this);
}
