#include "openmmdpd/DPDSoftRepulsionForce.h"
#include "openmmdpd/internal/DPDSoftRepulsionForceImpl.h"
#include "openmmdpd/internal/ParameterChecks.h"
#include <cmath>

using namespace DPDPlugin;
using OpenMM::OpenMMException;

namespace {

// Every message names the force first.
void check(bool ok, const std::string& message) {
    require(ok, "DPDSoftRepulsionForce: " + message);
}

} // namespace

DPDSoftRepulsionForce::DPDSoftRepulsionForce(double defaultA, double defaultCutoff) :
        defaultA(0), defaultCutoff(1), method(CutoffPeriodic), types("DPDSoftRepulsionForce", "a", "kJ/mol/nm") {
    setDefaultA(defaultA);
    setDefaultCutoff(defaultCutoff);
}

void DPDSoftRepulsionForce::setDefaultA(double a) {
    check(std::isfinite(a) && a >= 0, "defaultA must be >= 0 kJ/mol/nm, got " + numberText(a));
    defaultA = a;
}

void DPDSoftRepulsionForce::setDefaultCutoff(double cutoff) {
    check(std::isfinite(cutoff) && cutoff > 0, "defaultCutoff must be > 0 nm, got " + numberText(cutoff));
    defaultCutoff = cutoff;
}

void DPDSoftRepulsionForce::setNonbondedMethod(NonbondedMethod m) {
    check(m == CutoffNonPeriodic || m == CutoffPeriodic,
          "nonbondedMethod must be CutoffNonPeriodic (1) or CutoffPeriodic (2), got " + std::to_string((int) m));
    method = m;
}

void DPDSoftRepulsionForce::getTypePairParameters(int pairIndex, int& type1, int& type2, double& a, double& cutoff) const {
    const ParticleTypeTable::TypePair& p = types.getTypePair(pairIndex);
    type1 = p.type1;
    type2 = p.type2;
    a = p.value;
    cutoff = p.cutoff;
}

int DPDSoftRepulsionForce::addExclusion(int particle1, int particle2) {
    check(particle1 >= 0 && particle2 >= 0 && particle1 != particle2,
            "an exclusion's particle1 and particle2 must be two different particle indices >= 0, got " +
            std::to_string(particle1) + ", " + std::to_string(particle2));
    exclusions.push_back({particle1, particle2});
    return (int) exclusions.size() - 1;
}

void DPDSoftRepulsionForce::getExclusionParticles(int index, int& particle1, int& particle2) const {
    check(index >= 0 && index < (int) exclusions.size(),
          "index must be in [0, " + std::to_string(exclusions.size()) + "), got " + std::to_string(index));
    particle1 = exclusions[index].first;
    particle2 = exclusions[index].second;
}

void DPDSoftRepulsionForce::updateParametersInContext(OpenMM::Context& context) {
    dynamic_cast<DPDSoftRepulsionForceImpl&>(getImplInContext(context)).updateParametersInContext(getContextImpl(context));
}

OpenMM::ForceImpl* DPDSoftRepulsionForce::createImpl() const {
    return new DPDSoftRepulsionForceImpl(*this);
}
