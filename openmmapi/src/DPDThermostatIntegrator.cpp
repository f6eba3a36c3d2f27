#include "openmmdpd/DPDThermostatIntegrator.h"
#include "openmmdpd/DPDKernels.h"
#include "openmm/Context.h"
#include "openmm/internal/ContextImpl.h"
#include "openmm/OpenMMException.h"
#include "openmm/System.h"
#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>

using namespace DPDPlugin;
using OpenMM::OpenMMException;

namespace {

void require(bool ok, const std::string& message) {
    if (!ok)
        throw OpenMMException(message);
}

std::string str(double x) {
    std::ostringstream s;
    s << x;
    return s.str();
}

} // namespace

DPDThermostatIntegrator::DPDThermostatIntegrator(double temperature, double defaultFriction, double defaultCutoff, double stepSize) :
        temperature(0), defaultFriction(0), defaultCutoff(1), randomNumberSeed(0) {
    // Named checks first: nothing is stored unless every argument is valid.
    require(std::isfinite(temperature) && temperature >= 0, "temperature must be >= 0 K, got " + str(temperature));
    require(std::isfinite(defaultFriction) && defaultFriction >= 0, "defaultFriction must be >= 0 /ps, got " + str(defaultFriction));
    require(std::isfinite(defaultCutoff) && defaultCutoff > 0, "defaultCutoff must be > 0 nm, got " + str(defaultCutoff));
    require(std::isfinite(stepSize) && stepSize > 0, "stepSize must be > 0 ps, got " + str(stepSize));
    this->temperature = temperature;
    this->defaultFriction = defaultFriction;
    this->defaultCutoff = defaultCutoff;
    OpenMM::Integrator::setStepSize(stepSize);
}

void DPDThermostatIntegrator::setTemperature(double temp) {
    require(std::isfinite(temp) && temp >= 0, "temperature must be >= 0 K, got " + str(temp));
    temperature = temp;
}

void DPDThermostatIntegrator::setDefaultFriction(double friction) {
    require(std::isfinite(friction) && friction >= 0, "defaultFriction must be >= 0 /ps, got " + str(friction));
    defaultFriction = friction;
}

void DPDThermostatIntegrator::setDefaultCutoff(double cutoff) {
    require(std::isfinite(cutoff) && cutoff > 0, "defaultCutoff must be > 0 nm, got " + str(cutoff));
    defaultCutoff = cutoff;
}

void DPDThermostatIntegrator::setStepSize(double size) {
    require(std::isfinite(size) && size > 0, "stepSize must be > 0 ps, got " + str(size));
    OpenMM::Integrator::setStepSize(size);
}

int DPDThermostatIntegrator::getParticleType(int index) const {
    require(index >= 0, "particle index must be >= 0, got " + std::to_string(index));
    auto it = particleType.find(index);
    return it == particleType.end() ? 0 : it->second;
}

void DPDThermostatIntegrator::setParticleType(int index, int type) {
    require(index >= 0, "particle index must be >= 0, got " + std::to_string(index));
    require(type >= 0, "particle type must be >= 0, got " + std::to_string(type));
    if (type == 0)
        particleType.erase(index);
    else
        particleType[index] = type;
}

void DPDThermostatIntegrator::checkTypePair(int type1, int type2, double friction, double cutoff) const {
    require(type1 >= 0, "type1 must be >= 0, got " + std::to_string(type1));
    require(type2 >= 0, "type2 must be >= 0, got " + std::to_string(type2));
    require(std::isfinite(friction) && friction >= 0, "friction must be >= 0 /ps, got " + str(friction));
    require(std::isfinite(cutoff) && cutoff > 0, "cutoff must be > 0 nm, got " + str(cutoff));
}

int DPDThermostatIntegrator::addTypePair(int type1, int type2, double friction, double cutoff) {
    checkTypePair(type1, type2, friction, cutoff);
    for (const TypePair& p : typePairs)
        require(!((p.type1 == type1 && p.type2 == type2) || (p.type1 == type2 && p.type2 == type1)),
                "type pair (" + std::to_string(type1) + ", " + std::to_string(type2) + ") was already added");
    typePairs.push_back({type1, type2, friction, cutoff});
    return (int) typePairs.size() - 1;
}

void DPDThermostatIntegrator::getTypePairParameters(int pairIndex, int& type1, int& type2, double& friction, double& cutoff) const {
    require(pairIndex >= 0 && pairIndex < (int) typePairs.size(),
            "pairIndex must be in [0, " + std::to_string(typePairs.size()) + "), got " + std::to_string(pairIndex));
    const TypePair& p = typePairs[pairIndex];
    type1 = p.type1;
    type2 = p.type2;
    friction = p.friction;
    cutoff = p.cutoff;
}

void DPDThermostatIntegrator::setTypePairParameters(int pairIndex, int type1, int type2, double friction, double cutoff) {
    require(pairIndex >= 0 && pairIndex < (int) typePairs.size(),
            "pairIndex must be in [0, " + std::to_string(typePairs.size()) + "), got " + std::to_string(pairIndex));
    checkTypePair(type1, type2, friction, cutoff);
    for (int i = 0; i < (int) typePairs.size(); i++)
        require(i == pairIndex || !((typePairs[i].type1 == type1 && typePairs[i].type2 == type2) || (typePairs[i].type1 == type2 && typePairs[i].type2 == type1)),
                "type pair (" + std::to_string(type1) + ", " + std::to_string(type2) + ") is already entry " + std::to_string(i));
    typePairs[pairIndex] = {type1, type2, friction, cutoff};
}

double DPDThermostatIntegrator::getMaxCutoff() const {
    double c = defaultCutoff;
    for (const TypePair& p : typePairs)
        c = std::max(c, p.cutoff);
    return c;
}

double DPDThermostatIntegrator::getMaxFriction() const {
    double f = defaultFriction;
    for (const TypePair& p : typePairs)
        f = std::max(f, p.friction);
    return f;
}

void DPDThermostatIntegrator::validate(const OpenMM::System& system) const {
    const std::string name = className();
    int n = system.getNumParticles();
    std::set<int> usedTypes = {0};
    for (auto& entry : particleType) {
        require(entry.first < n, name + ": setParticleType was given particle index " + std::to_string(entry.first) +
                ", but the System has only " + std::to_string(n) + " particles");
        usedTypes.insert(entry.second);
    }
    for (int i = 0; i < (int) typePairs.size(); i++)
        for (int t : {typePairs[i].type1, typePairs[i].type2})
            require(usedTypes.count(t) != 0, name + ": type pair " + std::to_string(i) + " names particle type " +
                    std::to_string(t) + ", which no particle has (unknown particle type)");
    require(system.getNumConstraints() == 0, name + " does not support constraints; the System has " +
            std::to_string(system.getNumConstraints()));
    if (system.usesPeriodicBoundaryConditions()) {
        OpenMM::Vec3 a, b, c;
        system.getDefaultPeriodicBoxVectors(a, b, c);
        double halfWidth = 0.5 * std::min(a[0], std::min(b[1], c[2]));
        require(getMaxCutoff() <= halfWidth, name + ": the thermostat cutoff (" + str(getMaxCutoff()) +
                " nm) must not exceed half the periodic box width (" + str(halfWidth) + " nm)");
    }
}

void DPDThermostatIntegrator::initialize(OpenMM::ContextImpl& contextRef) {
    if (owner != nullptr && &contextRef.getOwner() != owner)
        throw OpenMMException("This Integrator is already bound to a context");
    validate(contextRef.getSystem());
    kernel = contextRef.getPlatform().createKernel(kernelName(), contextRef);
    kernel.getAs<IntegrateDPDStepKernel>().initialize(contextRef.getSystem(), *this);
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
        kernel.getAs<IntegrateDPDStepKernel>().invalidateForces();
}

double DPDThermostatIntegrator::computeKineticEnergy() {
    return kernel.getAs<IntegrateDPDStepKernel>().computeKineticEnergy(*context);
}

void DPDThermostatIntegrator::step(int steps) {
    if (context == nullptr)
        throw OpenMMException("This Integrator is not bound to a context!");
    // Parameters may have been changed since the Context was created.
    validate(context->getSystem());
    IntegrateDPDStepKernel& stepKernel = kernel.getAs<IntegrateDPDStepKernel>();
    for (int i = 0; i < steps; i++) {
        if (context->updateContextState())
            stepKernel.invalidateForces();
        stepKernel.execute(*context, *this);
    }
}

void DPDThermostatIntegrator::createCheckpoint(std::ostream& stream) const {
    kernel.getAs<const IntegrateDPDStepKernel>().createCheckpoint(*context, stream);
}

void DPDThermostatIntegrator::loadCheckpoint(std::istream& stream) {
    kernel.getAs<IntegrateDPDStepKernel>().loadCheckpoint(*context, stream);
}
