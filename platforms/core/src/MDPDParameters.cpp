#include "openmmdpd/MDPDParameters.h"

using namespace DPDPlugin;

namespace {

constexpr double PI = 3.14159265358979323846;

TypePairTable attractionTable(int numParticles, const MDPDForce& force) {
    std::vector<TypePairTable::Entry> entries(force.getNumTypePairs());
    for (int k = 0; k < force.getNumTypePairs(); k++) {
        TypePairTable::Entry& e = entries[k];
        force.getTypePairParameters(k, e.type1, e.type2, e.value, e.cutoff);
    }
    return TypePairTable(numParticles, force.getParticleTypes(), force.getDefaultA(), force.getDefaultCutoff(), entries);
}

} // namespace

MDPDParameters::MDPDParameters(int numParticles, const MDPDForce& force) :
        table(attractionTable(numParticles, force)), bOfType(table.getNumTypes(), force.getDefaultB()),
        densityCutoff(force.getDensityCutoff()), inverseDensityCutoff(1 / force.getDensityCutoff()) {
    for (int i = 0; i < numParticles; i++)
        bOfType[table.typeOf(i)] = force.getTypeB(force.getParticleType(i));
    const double rd = densityCutoff;
    densityNorm = 15 / (2 * PI * rd * rd * rd);
    energyFactor = PI * rd * rd * rd * rd / 30;
}
