#include "openmmdpd/DPDVVIntegrator.h"
#include "openmmdpd/DPDKernels.h"
#include "openmm/OpenMMException.h"
#include <cmath>
#include <string>

using namespace DPDPlugin;
using OpenMM::OpenMMException;

DPDVVIntegrator::DPDVVIntegrator(double temperature, double defaultFriction, double defaultCutoff, double stepSize) :
        DPDThermostatIntegrator(temperature, defaultFriction, defaultCutoff, stepSize),
        variant(GrootWarren), lambda(0.5), tolerance(1e-6), maxIterations(6) {
}

void DPDVVIntegrator::setVariant(Variant v) {
    if (v != GrootWarren && v != DPDVV && v != SelfConsistent)
        throw OpenMMException("variant must be GrootWarren (0), DPDVV (1) or SelfConsistent (2), got " + std::to_string((int) v));
    variant = v;
}

void DPDVVIntegrator::setLambda(double value) {
    if (!(value >= 0 && value <= 1))
        throw OpenMMException("lambda must be in [0, 1], got " + std::to_string(value));
    lambda = value;
}

void DPDVVIntegrator::setMaxIterations(int iterations) {
    if (iterations < 1)
        throw OpenMMException("maxIterations must be >= 1, got " + std::to_string(iterations));
    maxIterations = iterations;
}

void DPDVVIntegrator::setTolerance(double tol) {
    if (!(tol >= 0 && std::isfinite(tol)))
        throw OpenMMException("tolerance must be >= 0, got " + std::to_string(tol));
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
