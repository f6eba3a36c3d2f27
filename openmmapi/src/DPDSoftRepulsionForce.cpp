#include "openmmdpd/DPDSoftRepulsionForce.h"
#include "openmmdpd/internal/DPDSoftRepulsionForceImpl.h"
#include "openmm/OpenMMException.h"
#include <algorithm>
#include <cmath>
#include <sstream>

using namespace DPDPlugin;
using OpenMM::OpenMMException;

namespace {

void require(bool ok, const std::string& message) {
    if (!ok)
        throw OpenMMException("DPDSoftRepulsionForce: " + message);
}

std::string str(double x) {
    std::ostringstream s;
    s << x;
    return s.str();
}

} // namespace

DPDSoftRepulsionForce::DPDSoftRepulsionForce(double defaultA, double defaultCutoff) : defaultA(0), defaultCutoff(1), method(CutoffPeriodic) {
    setDefaultA(defaultA);
    setDefaultCutoff(defaultCutoff);
}

void DPDSoftRepulsionForce::setDefaultA(double a) {
    require(std::isfinite(a) && a >= 0, "defaultA must be >= 0 kJ/mol/nm, got " + str(a));
    defaultA = a;
}

void DPDSoftRepulsionForce::setDefaultCutoff(double cutoff) {
    require(std::isfinite(cutoff) && cutoff > 0, "defaultCutoff must be > 0 nm, got " + str(cutoff));
    defaultCutoff = cutoff;
}

void DPDSoftRepulsionForce::setNonbondedMethod(NonbondedMethod m) {
    require(m == CutoffNonPeriodic || m == CutoffPeriodic, "nonbondedMethod must be CutoffNonPeriodic (1) or CutoffPeriodic (2)");
    method = m;
}

int DPDSoftRepulsionForce::getParticleType(int index) const {
    require(index >= 0, "particle index must be >= 0, got " + std::to_string(index));
    auto it = particleType.find(index);
    return it == particleType.end() ? 0 : it->second;
}

void DPDSoftRepulsionForce::setParticleType(int index, int type) {
    require(index >= 0, "particle index must be >= 0, got " + std::to_string(index));
    require(type >= 0, "particle type must be >= 0, got " + std::to_string(type));
    if (type == 0)
        particleType.erase(index);
    else
        particleType[index] = type;
}

void DPDSoftRepulsionForce::checkTypePair(int type1, int type2, double a, double cutoff) const {
    require(type1 >= 0 && type2 >= 0, "type1 and type2 must be >= 0, got " + std::to_string(type1) + ", " + std::to_string(type2));
    require(std::isfinite(a) && a >= 0, "a must be >= 0 kJ/mol/nm, got " + str(a));
    require(std::isfinite(cutoff) && cutoff > 0, "cutoff must be > 0 nm, got " + str(cutoff));
}

int DPDSoftRepulsionForce::addTypePair(int type1, int type2, double a, double cutoff) {
    checkTypePair(type1, type2, a, cutoff);
    for (const TypePair& p : typePairs)
        require(!((p.type1 == type1 && p.type2 == type2) || (p.type1 == type2 && p.type2 == type1)),
                "type pair (" + std::to_string(type1) + ", " + std::to_string(type2) + ") was already added");
    typePairs.push_back({type1, type2, a, cutoff});
    return (int) typePairs.size() - 1;
}

void DPDSoftRepulsionForce::getTypePairParameters(int pairIndex, int& type1, int& type2, double& a, double& cutoff) const {
    require(pairIndex >= 0 && pairIndex < (int) typePairs.size(), "pairIndex out of range: " + std::to_string(pairIndex));
    const TypePair& p = typePairs[pairIndex];
    type1 = p.type1;
    type2 = p.type2;
    a = p.a;
    cutoff = p.cutoff;
}

void DPDSoftRepulsionForce::setTypePairParameters(int pairIndex, int type1, int type2, double a, double cutoff) {
    require(pairIndex >= 0 && pairIndex < (int) typePairs.size(), "pairIndex out of range: " + std::to_string(pairIndex));
    checkTypePair(type1, type2, a, cutoff);
    typePairs[pairIndex] = {type1, type2, a, cutoff};
}

int DPDSoftRepulsionForce::addExclusion(int particle1, int particle2) {
    require(particle1 >= 0 && particle2 >= 0 && particle1 != particle2,
            "an exclusion needs two different particle indices >= 0, got " + std::to_string(particle1) + ", " + std::to_string(particle2));
    exclusions.push_back({particle1, particle2});
    return (int) exclusions.size() - 1;
}

void DPDSoftRepulsionForce::getExclusionParticles(int index, int& particle1, int& particle2) const {
    require(index >= 0 && index < (int) exclusions.size(), "exclusion index out of range: " + std::to_string(index));
    particle1 = exclusions[index].first;
    particle2 = exclusions[index].second;
}

double DPDSoftRepulsionForce::getMaxCutoff() const {
    double c = defaultCutoff;
    for (const TypePair& p : typePairs)
        c = std::max(c, p.cutoff);
    return c;
}

void DPDSoftRepulsionForce::updateParametersInContext(OpenMM::Context& context) {
    dynamic_cast<DPDSoftRepulsionForceImpl&>(getImplInContext(context)).updateParametersInContext(getContextImpl(context));
}

OpenMM::ForceImpl* DPDSoftRepulsionForce::createImpl() const {
    return new DPDSoftRepulsionForceImpl(*this);
}
