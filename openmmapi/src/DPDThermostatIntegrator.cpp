#include "openmmdpd/DPDThermostatIntegrator.h"
#include "openmmdpd/DPDKernels.h"
#include "openmm/Context.h"
#include "openmm/internal/ContextImpl.h"
#include "openmmdpd/internal/ParameterChecks.h"
#include "openmm/System.h"
#include <algorithm>
#include <cmath>

using namespace DPDPlugin;
using OpenMM::OpenMMException;

DPDThermostatIntegrator::DPDThermostatIntegrator(double temperature, double defaultFriction, double defaultCutoff, double stepSize) :
        temperature(0), defaultFriction(0), defaultCutoff(1), randomNumberSeed(0), types("friction", "/ps") {
    // Named checks first: nothing is stored unless every argument is valid.
    require(std::isfinite(temperature) && temperature >= 0, "temperature must be >= 0 K, got " + numberText(temperature));
    require(std::isfinite(defaultFriction) && defaultFriction >= 0, "defaultFriction must be >= 0 /ps, got " + numberText(defaultFriction));
    require(std::isfinite(defaultCutoff) && defaultCutoff > 0, "defaultCutoff must be > 0 nm, got " + numberText(defaultCutoff));
    require(std::isfinite(stepSize) && stepSize > 0, "stepSize must be > 0 ps, got " + numberText(stepSize));
    this->temperature = temperature;
    this->defaultFriction = defaultFriction;
    this->defaultCutoff = defaultCutoff;
    OpenMM::Integrator::setStepSize(stepSize);
}

void DPDThermostatIntegrator::setTemperature(double temp) {
    require(std::isfinite(temp) && temp >= 0, "temperature must be >= 0 K, got " + numberText(temp));
    temperature = temp;
    parametersVersion++;
}

void DPDThermostatIntegrator::setDefaultFriction(double friction) {
    require(std::isfinite(friction) && friction >= 0, "defaultFriction must be >= 0 /ps, got " + numberText(friction));
    defaultFriction = friction;
    parametersVersion++;
}

void DPDThermostatIntegrator::setDefaultCutoff(double cutoff) {
    require(std::isfinite(cutoff) && cutoff > 0, "defaultCutoff must be > 0 nm, got " + numberText(cutoff));
    defaultCutoff = cutoff;
    parametersVersion++;
}

void DPDThermostatIntegrator::setInstabilityThreshold(double factor) {
    require(std::isfinite(factor) && factor >= 0,
            "instabilityThreshold must be >= 0 (a multiple of kT; 0 turns the check off), got " + numberText(factor));
    instabilityThreshold = factor;
    parametersVersion++;
}

void DPDThermostatIntegrator::setStepSize(double size) {
    require(std::isfinite(size) && size > 0, "stepSize must be > 0 ps, got " + numberText(size));
    OpenMM::Integrator::setStepSize(size);
}

void DPDThermostatIntegrator::getTypePairParameters(int pairIndex, int& type1, int& type2, double& friction, double& cutoff) const {
    const ParticleTypeTable::TypePair& p = types.getTypePair(pairIndex);
    type1 = p.type1;
    type2 = p.type2;
    friction = p.value;
    cutoff = p.cutoff;
}

void DPDThermostatIntegrator::validate(const OpenMM::System& system) const {
    const std::string name = className();
    types.validate(system, name);
    require(system.getNumConstraints() == 0, name + " does not support constraints; the System has " +
            std::to_string(system.getNumConstraints()));
    if (system.usesPeriodicBoundaryConditions()) {
        OpenMM::Vec3 a, b, c;
        system.getDefaultPeriodicBoxVectors(a, b, c);
        double halfWidth = 0.5 * std::min(a[0], std::min(b[1], c[2]));
        require(getMaxCutoff() <= halfWidth, name + ": the thermostat cutoff (" + numberText(getMaxCutoff()) +
                " nm) must not exceed half the periodic box width (" + numberText(halfWidth) + " nm)");
    }
}

void DPDThermostatIntegrator::initialize(OpenMM::ContextImpl& contextRef) {
    if (owner != nullptr && &contextRef.getOwner() != owner)
        throw OpenMMException("This Integrator is already bound to a context");
    validate(contextRef.getSystem());
    kernel = contextRef.getPlatform().createKernel(kernelName(), contextRef);
    initializeStepKernel(kernel, contextRef.getSystem());
    context = &contextRef;
    owner = &contextRef.getOwner();
}

void DPDThermostatIntegrator::cleanup() {
    kernel = OpenMM::Kernel();
    context = nullptr;
}

std::vector<std::string> DPDThermostatIntegrator::getKernelNames() {
    return {kernelName()};
}

void DPDThermostatIntegrator::stateChanged(OpenMM::State::DataType changed) {
    if (context != nullptr)
        kernel.getAs<DPDStepKernel>().invalidateForces();
}

double DPDThermostatIntegrator::computeKineticEnergy() {
    return kernel.getAs<DPDStepKernel>().computeKineticEnergy(*context);
}

void DPDThermostatIntegrator::step(int steps) {
    if (context == nullptr)
        throw OpenMMException("This Integrator is not bound to a context!");
    // Parameters may have been changed since the Context was created.
    validate(context->getSystem());
    DPDStepKernel& stepKernel = kernel.getAs<DPDStepKernel>();
    for (int i = 0; i < steps; i++) {
        if (context->updateContextState())
            stepKernel.invalidateForces();
        executeStepKernel(kernel, *context);
    }
}

const OpenMM::Kernel& DPDThermostatIntegrator::getStepKernel() const {
    if (context == nullptr)
        throw OpenMMException(std::string(className()) + " is not bound to a Context");
    return kernel;
}

void DPDThermostatIntegrator::createCheckpoint(std::ostream& stream) const {
    kernel.getAs<const DPDStepKernel>().createCheckpoint(*context, stream);
}

void DPDThermostatIntegrator::loadCheckpoint(std::istream& stream) {
    kernel.getAs<DPDStepKernel>().loadCheckpoint(*context, stream);
}
