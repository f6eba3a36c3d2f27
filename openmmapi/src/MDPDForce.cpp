#include "openmmdpd/MDPDForce.h"
#include "openmmdpd/internal/MDPDForceImpl.h"
#include "openmmdpd/internal/ParameterChecks.h"
#include <algorithm>
#include <cmath>

using namespace DPDPlugin;

namespace {

// Every message names the force first.
void check(bool ok, const std::string& message) {
    require(ok, "MDPDForce: " + message);
}

void checkB(double b, const std::string& name) {
    check(std::isfinite(b) && b >= 0, name + " must be >= 0 kJ/mol/nm, got " + numberText(b));
}

} // namespace

MDPDForce::MDPDForce(double defaultA, double defaultB, double defaultCutoff, double densityCutoff) :
        defaultA(0), defaultB(0), defaultCutoff(1), densityCutoff(0), method(CutoffPeriodic), types("MDPDForce", "a", "kJ/mol/nm", true) {
    setDefaultA(defaultA);
    setDefaultB(defaultB);
    setDefaultCutoff(defaultCutoff);
    setDensityCutoff(densityCutoff);
}

void MDPDForce::setDefaultA(double a) {
    check(std::isfinite(a), "defaultA must be finite, got " + numberText(a));
    defaultA = a;
}

void MDPDForce::setDefaultB(double b) {
    checkB(b, "defaultB");
    defaultB = b;
}

void MDPDForce::checkPairCutoff(double cutoff) const {
    check(std::isfinite(cutoff) && cutoff > 0, "cutoff must be > 0 nm, got " + numberText(cutoff));
    check(cutoff >= densityCutoff, "cutoff must be >= the densityCutoff rd (" + numberText(densityCutoff) + " nm), got " +
          numberText(cutoff) + " nm");
}

void MDPDForce::setDefaultCutoff(double cutoff) {
    check(std::isfinite(cutoff) && cutoff > 0, "defaultCutoff must be > 0 nm, got " + numberText(cutoff));
    check(cutoff >= densityCutoff, "defaultCutoff must be >= the densityCutoff rd (" + numberText(densityCutoff) + " nm), got " +
          numberText(cutoff) + " nm");
    defaultCutoff = cutoff;
}

double MDPDForce::getMinCutoff() const {
    double c = defaultCutoff;
    for (int k = 0; k < types.getNumTypePairs(); k++)
        c = std::min(c, types.getTypePair(k).cutoff);
    return c;
}

void MDPDForce::setDensityCutoff(double cutoff) {
    check(std::isfinite(cutoff) && cutoff > 0 && cutoff <= getMinCutoff(),
          "densityCutoff must be in (0, " + numberText(getMinCutoff()) + "] nm (at most every cutoff rc), got " + numberText(cutoff));
    densityCutoff = cutoff;
}

void MDPDForce::setNonbondedMethod(NonbondedMethod m) {
    check(m == CutoffNonPeriodic || m == CutoffPeriodic,
          "nonbondedMethod must be CutoffNonPeriodic (1) or CutoffPeriodic (2), got " + std::to_string((int) m));
    method = m;
}

int MDPDForce::addTypePair(int type1, int type2, double a, double cutoff) {
    checkPairCutoff(cutoff);
    return types.addTypePair(type1, type2, a, cutoff);
}

void MDPDForce::setTypePairParameters(int pairIndex, int type1, int type2, double a, double cutoff) {
    checkPairCutoff(cutoff);
    types.setTypePair(pairIndex, type1, type2, a, cutoff);
}

void MDPDForce::getTypePairParameters(int pairIndex, int& type1, int& type2, double& a, double& cutoff) const {
    const ParticleTypeTable::TypePair& p = types.getTypePair(pairIndex);
    type1 = p.type1;
    type2 = p.type2;
    a = p.value;
    cutoff = p.cutoff;
}

void MDPDForce::setTypeB(int type, double b) {
    check(type >= 0, "type must be >= 0, got " + std::to_string(type));
    checkB(b, "B");
    typeB[type] = b;
}

double MDPDForce::getTypeB(int type) const {
    check(type >= 0, "type must be >= 0, got " + std::to_string(type));
    const auto it = typeB.find(type);
    return it == typeB.end() ? defaultB : it->second;
}

int MDPDForce::addExclusion(int particle1, int particle2) {
    check(particle1 >= 0 && particle2 >= 0 && particle1 != particle2,
          "an exclusion's particle1 and particle2 must be two different particle indices >= 0, got " +
          std::to_string(particle1) + ", " + std::to_string(particle2));
    exclusions.push_back({particle1, particle2});
    return (int) exclusions.size() - 1;
}

void MDPDForce::getExclusionParticles(int index, int& particle1, int& particle2) const {
    check(index >= 0 && index < (int) exclusions.size(),
          "index must be in [0, " + std::to_string(exclusions.size()) + "), got " + std::to_string(index));
    particle1 = exclusions[index].first;
    particle2 = exclusions[index].second;
}

void MDPDForce::updateParametersInContext(OpenMM::Context& context) {
    dynamic_cast<MDPDForceImpl&>(getImplInContext(context)).updateParametersInContext(getContextImpl(context));
}

OpenMM::ForceImpl* MDPDForce::createImpl() const {
    return new MDPDForceImpl(*this);
}
