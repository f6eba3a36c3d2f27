#include "openmmdpd/DPDThermostatIntegrator.h"
#include "openmmdpd/DPDKernels.h"
#include "openmm/Context.h"
#include "openmm/internal/ContextImpl.h"
#include "openmmdpd/internal/ForceTerms.h"
#include "openmmdpd/internal/ParameterChecks.h"
#include "openmm/System.h"
#include "openmm/CMMotionRemover.h"
#include <algorithm>
#include <cmath>

using namespace DPDPlugin;
using OpenMM::OpenMMException;

DPDThermostatIntegrator::DPDThermostatIntegrator(const std::string& className, double temperature, double defaultFriction,
                                                 double defaultCutoff, double stepSize) :
        name(className), temperature(0), defaultFriction(0), defaultCutoff(1), randomNumberSeed(0),
        types(className, "friction", "/ps") {
    // Named checks first: nothing is stored unless every argument is valid.
    checkTemperature(temperature);
    checkFriction(defaultFriction);
    checkCutoff(defaultCutoff);
    checkStepSize(stepSize);
    this->temperature = temperature;
    this->defaultFriction = defaultFriction;
    this->defaultCutoff = defaultCutoff;
    OpenMM::Integrator::setStepSize(stepSize);
    // OpenMM's Integrator leaves it unset; OpenMM's own integrators start at 1e-5 too.
    OpenMM::Integrator::setConstraintTolerance(DEFAULT_CONSTRAINT_TOLERANCE);
}

void DPDThermostatIntegrator::checkTemperature(double temp) const {
    require(std::isfinite(temp) && temp >= 0, name + ": temperature must be >= 0 K, got " + numberText(temp));
}

void DPDThermostatIntegrator::checkFriction(double friction) const {
    require(std::isfinite(friction) && friction >= 0, name + ": defaultFriction must be >= 0 /ps, got " + numberText(friction));
}

void DPDThermostatIntegrator::checkCutoff(double cutoff) const {
    require(std::isfinite(cutoff) && cutoff > 0, name + ": defaultCutoff must be > 0 nm, got " + numberText(cutoff));
}

void DPDThermostatIntegrator::checkStepSize(double size) const {
    require(std::isfinite(size) && size > 0, name + ": stepSize must be > 0 ps, got " + numberText(size));
}

void DPDThermostatIntegrator::setTemperature(double temp) {
    checkTemperature(temp);
    temperature = temp;
    parametersVersion++;
}

void DPDThermostatIntegrator::setDefaultFriction(double friction) {
    checkFriction(friction);
    defaultFriction = friction;
    parametersVersion++;
}

void DPDThermostatIntegrator::setDefaultCutoff(double cutoff) {
    checkCutoff(cutoff);
    defaultCutoff = cutoff;
    parametersVersion++;
}

void DPDThermostatIntegrator::checkWeightExponent(const std::string& parameter, double s) const {
    require(std::isfinite(s) && s > 0, name + ": " + parameter + " must be > 0 (the exponent s of wD = (1 - r/rc)^s; "
            "2 is standard DPD), got " + numberText(s));
}

void DPDThermostatIntegrator::setDefaultWeightExponent(double s) {
    checkWeightExponent("defaultWeightExponent", s);
    defaultWeightExponent = s;
    parametersVersion++;
}

double DPDThermostatIntegrator::getTypePairWeightExponent(int pairIndex) const {
    int type1, type2;
    double friction, cutoff;
    getTypePairParameters(pairIndex, type1, type2, friction, cutoff);  // checks the index
    const auto own = typePairWeightExponent.find(pairIndex);
    return own == typePairWeightExponent.end() ? defaultWeightExponent : own->second;
}

void DPDThermostatIntegrator::setTypePairWeightExponent(int pairIndex, double s) {
    getTypePairWeightExponent(pairIndex);  // checks the index
    checkWeightExponent("the weight exponent of type pair " + std::to_string(pairIndex), s);
    typePairWeightExponent[pairIndex] = s;
    parametersVersion++;
}

bool DPDThermostatIntegrator::hasStandardWeights() const {
    for (int k = 0; k < getNumTypePairs(); k++)
        if (getTypePairWeightExponent(k) != 2)
            return false;
    return defaultWeightExponent == 2;
}

void DPDThermostatIntegrator::checkTransverseFriction(const std::string& parameter, double friction) const {
    require(std::isfinite(friction) && friction >= 0, name + ": " + parameter + " must be >= 0 /ps, got " + numberText(friction));
}

void DPDThermostatIntegrator::setDefaultTransverseFriction(double friction) {
    checkTransverseFriction("defaultTransverseFriction", friction);
    defaultTransverseFriction = friction;
    parametersVersion++;
}

void DPDThermostatIntegrator::setDefaultTransverseWeightExponent(double s) {
    checkWeightExponent("defaultTransverseWeightExponent", s);
    defaultTransverseWeightExponent = s;
    parametersVersion++;
}

void DPDThermostatIntegrator::getTypePairTransverseFriction(int pairIndex, double& friction, double& weightExponent) const {
    getTypePairWeightExponent(pairIndex);  // checks the index
    const auto own = typePairTransverse.find(pairIndex);
    friction = (own == typePairTransverse.end() ? defaultTransverseFriction : own->second.first);
    weightExponent = (own == typePairTransverse.end() ? defaultTransverseWeightExponent : own->second.second);
}

void DPDThermostatIntegrator::setTypePairTransverseFriction(int pairIndex, double friction, double weightExponent) {
    getTypePairWeightExponent(pairIndex);  // checks the index
    const std::string pair = "type pair " + std::to_string(pairIndex);
    checkTransverseFriction("the transverse friction of " + pair, friction);
    checkWeightExponent("the transverse weight exponent of " + pair, weightExponent);
    typePairTransverse[pairIndex] = {friction, weightExponent};
    parametersVersion++;
}

bool DPDThermostatIntegrator::hasTransverseFriction() const {
    double friction, exponent;
    for (int k = 0; k < getNumTypePairs(); k++) {
        getTypePairTransverseFriction(k, friction, exponent);
        if (friction != 0)
            return true;
    }
    return defaultTransverseFriction != 0;
}

void DPDThermostatIntegrator::validateTransverseFriction(const OpenMM::System&) const {
    throw OpenMMException(name + ": transverse friction (setDefaultTransverseFriction, setTypePairTransverseFriction) is not "
                          "available for this integrator; DPDVVIntegrator, ShardlowIntegrator and LoweAndersenIntegrator's "
                          "PairOrnsteinUhlenbeck method have it");
}

void DPDThermostatIntegrator::refuseTransverseFrictionWithConstraints(const OpenMM::System& system) const {
    require(system.getNumConstraints() == 0, name + ": transverse friction is not available with constraints (the System has " +
            std::to_string(system.getNumConstraints()) + "): this scheme's pair impulses would have another effective mass "
            "for each direction across the pair; use DPDVVIntegrator, or bonds instead of constraints");
}

namespace {

std::pair<int, int> orderedPair(int a, int b) {
    return {std::min(a, b), std::max(a, b)};
}

} // namespace

void DPDThermostatIntegrator::checkException(int particle1, int particle2, double factor, int replacing) const {
    const std::string pair = std::to_string(particle1) + ", " + std::to_string(particle2);
    require(particle1 >= 0 && particle2 >= 0 && particle1 != particle2,
            name + ": a thermostat exception's particle1 and particle2 must be two different particle indices >= 0, got " + pair);
    require(std::isfinite(factor) && factor >= 0 && factor <= 1, name + ": the factor of the thermostat exception of particles " +
            pair + " must be in [0, 1] (it scales gamma by f and sigma by sqrt(f)), got " + numberText(factor));
    const auto known = exceptionIndex.find(orderedPair(particle1, particle2));
    require(known == exceptionIndex.end() || known->second == replacing,
            name + ": particles " + pair + " already have a thermostat exception (index " +
            (known == exceptionIndex.end() ? std::string() : std::to_string(known->second)) + ")");
}

int DPDThermostatIntegrator::addThermostatException(int particle1, int particle2, double factor) {
    checkException(particle1, particle2, factor, -1);
    exceptionIndex[orderedPair(particle1, particle2)] = (int) exceptions.size();
    exceptions.push_back({particle1, particle2, factor});
    parametersVersion++;
    return (int) exceptions.size() - 1;
}

void DPDThermostatIntegrator::getThermostatExceptionParameters(int index, int& particle1, int& particle2, double& factor) const {
    require(index >= 0 && index < (int) exceptions.size(),
            name + ": index must be in [0, " + std::to_string(exceptions.size()) + "), got " + std::to_string(index));
    particle1 = exceptions[index].particle1;
    particle2 = exceptions[index].particle2;
    factor = exceptions[index].factor;
}

void DPDThermostatIntegrator::setThermostatExceptionParameters(int index, int particle1, int particle2, double factor) {
    int old1, old2;
    double oldFactor;
    getThermostatExceptionParameters(index, old1, old2, oldFactor);  // checks the index
    checkException(particle1, particle2, factor, index);
    exceptionIndex.erase(orderedPair(old1, old2));
    exceptionIndex[orderedPair(particle1, particle2)] = index;
    exceptions[index] = {particle1, particle2, factor};
    parametersVersion++;
}

void DPDThermostatIntegrator::createThermostatExceptionsFromBonds(const std::vector<std::pair<int, int>>& bonds, double factor12,
                                                                  double factor13) {
    // The 1-2 and 1-3 pairs, each once, all checked before any is added.
    std::map<int, std::vector<int>> neighbours;
    for (const auto& bond : bonds) {
        neighbours[bond.first].push_back(bond.second);
        neighbours[bond.second].push_back(bond.first);
    }
    std::map<std::pair<int, int>, double> pairs;
    for (const auto& bond : bonds)
        pairs[orderedPair(bond.first, bond.second)] = factor12;
    if (factor13 != 1)
        for (const auto& centre : neighbours)
            for (int a : centre.second)
                for (int b : centre.second)
                    if (a != b && pairs.count(orderedPair(a, b)) == 0)
                        pairs[orderedPair(a, b)] = factor13;
    // A factor of 1 is no exception: such pairs are not listed (a list would only slow the step).
    for (const auto& pair : pairs)
        checkException(pair.first.first, pair.first.second, pair.second, -1);
    for (const auto& pair : pairs)
        if (pair.second != 1)
            addThermostatException(pair.first.first, pair.first.second, pair.second);
}

void DPDThermostatIntegrator::setInstabilityThreshold(double factor) {
    require(std::isfinite(factor) && factor >= 0,
            name + ": instabilityThreshold must be >= 0 (a multiple of kT; 0 turns the check off), got " + numberText(factor));
    instabilityThreshold = factor;
    parametersVersion++;
}

void DPDThermostatIntegrator::setShearRate(double rate) {
    require(std::isfinite(rate), name + ": shearRate must be a finite number (1/ps), got " + numberText(rate));
    shearRate = rate;
    parametersVersion++;
}

void DPDThermostatIntegrator::setPressureTensorEnabled(bool enabled) {
    require(!enabled || supportsPressureTensor(), name + ": the pressure tensor is not available for this integrator; "
            "it is for DPDVVIntegrator, ShardlowIntegrator, LoweAndersenIntegrator and EDPDIntegrator");
    pressureTensorEnabled = enabled;
}

std::vector<double> DPDThermostatIntegrator::getAveragePressureTensor(int part) const {
    require(part >= PressureTotal && part <= PressureThermostat,
            name + ": the pressure tensor part must be 0 (total), 1 (kinetic), 2 (conservative) or 3 (thermostat), got " +
                    std::to_string(part));
    return getStepKernel().getAs<const DPDStepKernel>().getAveragePressureTensor(part);
}

long long DPDThermostatIntegrator::getPressureTensorSampleCount() const {
    return getStepKernel().getAs<const DPDStepKernel>().getPressureTensorSampleCount();
}

void DPDThermostatIntegrator::resetPressureTensor() {
    getStepKernel();  // throws unless bound to a Context
    kernel.getAs<DPDStepKernel>().resetPressureTensor();
}

void DPDThermostatIntegrator::validateShear(const OpenMM::System& system) const {
    const std::string under = name + ": under shear (shearRate " + numberText(shearRate) + " /ps) ";
    require(system.usesPeriodicBoundaryConditions(), under + "the System must be periodic");
    OpenMM::Vec3 box[3];
    system.getDefaultPeriodicBoxVectors(box[0], box[1], box[2]);
    validateShearBox(box, "the System's default box");
    for (int k = 0; k < system.getNumForces(); k++) {
        const OpenMM::Force& force = system.getForce(k);
        require(force.usesPeriodicBoundaryConditions() || isBondedForce(force) ||
                        dynamic_cast<const OpenMM::CMMotionRemover*>(&force) != nullptr,
                under + "every Force must use periodic boundary conditions or be a bonded force (its molecule is wrapped "
                "as a whole); Force " + std::to_string(k) + " of the System is neither (a barostat, a non-periodic "
                "nonbonded or external force)");
    }
}

void DPDThermostatIntegrator::validateShearBox(const OpenMM::Vec3* box, const std::string& which) const {
    require(box[2][0] == 0 && box[2][1] == 0, name + ": under shear (shearRate " + numberText(shearRate) + " /ps) the third "
            "vector of " + which + " must be (0, 0, Lz): the boundary slides along x only; got (" + numberText(box[2][0]) +
            ", " + numberText(box[2][1]) + ", " + numberText(box[2][2]) + ")");
}

void DPDThermostatIntegrator::validateContextBox() const {
    if (!context->getSystem().usesPeriodicBoundaryConditions())
        return;
    OpenMM::Vec3 box[3];
    context->getPeriodicBoxVectors(box[0], box[1], box[2]);
    requireCutoffFitsBox(name, "the thermostat cutoff", getMaxCutoff(), box);
    if (shearRate != 0)
        validateShearBox(box, "the Context's box");
}

void DPDThermostatIntegrator::setStepSize(double size) {
    checkStepSize(size);
    OpenMM::Integrator::setStepSize(size);
}

void DPDThermostatIntegrator::setConstraintTolerance(double tol) {
    require(std::isfinite(tol) && tol > 0 && tol < 1,
            name + ": constraintTolerance must be > 0 and < 1 (relative), got " + numberText(tol));
    OpenMM::Integrator::setConstraintTolerance(tol);
}

void DPDThermostatIntegrator::getTypePairParameters(int pairIndex, int& type1, int& type2, double& friction, double& cutoff) const {
    const ParticleTypeTable::TypePair& p = types.getTypePair(pairIndex);
    type1 = p.type1;
    type2 = p.type2;
    friction = p.value;
    cutoff = p.cutoff;
}

void DPDThermostatIntegrator::validate(const OpenMM::System& system) const {
    types.validate(system);
    for (const Exception& e : exceptions)
        require(std::max(e.particle1, e.particle2) < system.getNumParticles(),
                name + ": the thermostat exception of particles " + std::to_string(e.particle1) + ", " +
                std::to_string(e.particle2) + " names a particle beyond the System's " + std::to_string(system.getNumParticles()));
    if (system.usesPeriodicBoundaryConditions()) {
        OpenMM::Vec3 box[3];
        system.getDefaultPeriodicBoxVectors(box[0], box[1], box[2]);
        requireCutoffFitsBox(name, "the thermostat cutoff", getMaxCutoff(), box);
    }
    if (shearRate != 0)
        validateShear(system);
    if (hasTransverseFriction())
        validateTransverseFriction(system);
}

void DPDThermostatIntegrator::initialize(OpenMM::ContextImpl& contextRef) {
    if (owner != nullptr && &contextRef.getOwner() != owner)
        throw OpenMMException(name + ": this integrator is already bound to another Context");
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
        throw OpenMMException(name + ": this integrator is not bound to a Context");
    // Parameters, and the Context's box, may have been changed since the Context was created.
    validate(context->getSystem());
    validateContextBox();
    DPDStepKernel& stepKernel = kernel.getAs<DPDStepKernel>();
    for (int i = 0; i < steps; i++) {
        if (context->updateContextState())
            stepKernel.invalidateForces();
        executeStepKernel(kernel, *context);
    }
}

const OpenMM::Kernel& DPDThermostatIntegrator::getStepKernel() const {
    if (context == nullptr)
        throw OpenMMException(name + ": this integrator is not bound to a Context");
    return kernel;
}

void DPDThermostatIntegrator::createCheckpoint(std::ostream& stream) const {
    kernel.getAs<const DPDStepKernel>().createCheckpoint(*context, stream);
}

void DPDThermostatIntegrator::loadCheckpoint(std::istream& stream) {
    kernel.getAs<DPDStepKernel>().loadCheckpoint(*context, stream);
}
