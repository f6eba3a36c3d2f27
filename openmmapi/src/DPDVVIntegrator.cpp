#include "openmmdpd/DPDVVIntegrator.h"
#include "openmmdpd/DPDKernels.h"
#include "openmmdpd/internal/ParameterChecks.h"
#include <cmath>
#include <string>

using namespace DPDPlugin;

DPDVVIntegrator::DPDVVIntegrator(double temperature, double defaultFriction, double defaultCutoff, double stepSize) :
        DPDThermostatIntegrator("DPDVVIntegrator", temperature, defaultFriction, defaultCutoff, stepSize),
        variant(GrootWarren), lambda(0.5), tolerance(1e-6), maxIterations(6) {
}

void DPDVVIntegrator::setVariant(Variant v) {
    require(v == GrootWarren || v == DPDVV || v == SelfConsistent,
            "DPDVVIntegrator: variant must be GrootWarren (0), DPDVV (1) or SelfConsistent (2), got " + std::to_string((int) v));
    variant = v;
}

void DPDVVIntegrator::setLambda(double value) {
    require(value >= 0 && value <= 1, "DPDVVIntegrator: lambda must be in [0, 1], got " + numberText(value));
    lambda = value;
}

void DPDVVIntegrator::setMaxIterations(int iterations) {
    require(iterations >= 1 && iterations <= MAX_ITERATIONS, "DPDVVIntegrator: maxIterations must be from 1 to " +
            std::to_string(MAX_ITERATIONS) + ", got " + std::to_string(iterations));
    maxIterations = iterations;
}

void DPDVVIntegrator::setTolerance(double tol) {
    require(tol >= 0 && std::isfinite(tol), "DPDVVIntegrator: tolerance must be >= 0, got " + numberText(tol));
    tolerance = tol;
}

std::string DPDVVIntegrator::kernelName() const {
    return IntegrateDPDVVStepKernel::Name();
}

void DPDVVIntegrator::initializeStepKernel(OpenMM::Kernel& kernel, const OpenMM::System& system) const {
    kernel.getAs<IntegrateDPDVVStepKernel>().initialize(system, *this);
}

void DPDVVIntegrator::executeStepKernel(OpenMM::Kernel& kernel, OpenMM::ContextImpl& context) const {
    kernel.getAs<IntegrateDPDVVStepKernel>().execute(context, *this);
}
