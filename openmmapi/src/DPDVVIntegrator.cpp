#include "openmmdpd/DPDVVIntegrator.h"
#include "openmmdpd/DPDKernels.h"
#include "openmm/Context.h"
#include "openmm/OpenMMException.h"
#include "openmm/internal/ContextImpl.h"
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

void DPDVVIntegrator::initialize(OpenMM::ContextImpl& contextRef) {
    if (owner != nullptr && &contextRef.getOwner() != owner)
        throw OpenMMException("This Integrator is already bound to a context");
    validateAgainstSystem(contextRef.getSystem());
    kernel = contextRef.getPlatform().createKernel(IntegrateDPDVVStepKernel::Name(), contextRef);
    kernel.getAs<IntegrateDPDVVStepKernel>().initialize(contextRef.getSystem(), *this);
    context = &contextRef;
    owner = &contextRef.getOwner();
}

void DPDVVIntegrator::cleanup() {
    kernel = OpenMM::Kernel();
    context = nullptr;
}

std::vector<std::string> DPDVVIntegrator::getKernelNames() {
    return {IntegrateDPDVVStepKernel::Name()};
}

void DPDVVIntegrator::stateChanged(OpenMM::State::DataType changed) {
    if (context != nullptr)
        kernel.getAs<IntegrateDPDVVStepKernel>().invalidateForces();
}

double DPDVVIntegrator::computeKineticEnergy() {
    return kernel.getAs<IntegrateDPDVVStepKernel>().computeKineticEnergy(*context, *this);
}

void DPDVVIntegrator::step(int steps) {
    if (context == nullptr)
        throw OpenMMException("This Integrator is not bound to a context!");
    for (int i = 0; i < steps; i++) {
        if (context->updateContextState())
            kernel.getAs<IntegrateDPDVVStepKernel>().invalidateForces();
        kernel.getAs<IntegrateDPDVVStepKernel>().execute(*context, *this);
    }
}

void DPDVVIntegrator::createCheckpoint(std::ostream& stream) const {
    kernel.getAs<const IntegrateDPDVVStepKernel>().createCheckpoint(*context, stream);
}

void DPDVVIntegrator::loadCheckpoint(std::istream& stream) {
    kernel.getAs<IntegrateDPDVVStepKernel>().loadCheckpoint(*context, stream);
}
