#include "openmmdpd/ReferenceSoftRepulsionKernel.h"
#include "openmmdpd/ExcludedPairs.h"
#include "openmmdpd/PairEvaluators.h"
#include "openmmdpd/PressureTensor.h"
#include "openmmdpd/ReferencePairList.h"
#include "openmm/internal/ContextImpl.h"
#include "ReferencePlatform.h"
#include <algorithm>

using namespace DPDPlugin;
using OpenMM::Vec3;

void ReferenceSoftRepulsionKernel::initialize(const OpenMM::System& system, const DPDSoftRepulsionForce& force) {
    numParticles = system.getNumParticles();
    periodic = force.usesPeriodicBoundaryConditions();
    for (const std::pair<int, int>& pair : exclusionPairs(force))
        exclusions.insert(std::minmax(pair.first, pair.second));
    setParameters(force);
}

void ReferenceSoftRepulsionKernel::copyParametersToContext(OpenMM::ContextImpl&, const DPDSoftRepulsionForce& force) {
    setParameters(force);
}

void ReferenceSoftRepulsionKernel::setParameters(const DPDSoftRepulsionForce& force) {
    std::vector<TypePairTable::Entry> entries(force.getNumTypePairs());
    for (int k = 0; k < force.getNumTypePairs(); k++) {
        TypePairTable::Entry& e = entries[k];
        force.getTypePairParameters(k, e.type1, e.type2, e.value, e.cutoff);
    }
    table.reset(new TypePairTable(numParticles, force.getParticleTypes(), force.getDefaultA(), force.getDefaultCutoff(), entries));
}

template <class Body>
void ReferenceSoftRepulsionKernel::forEachPair(OpenMM::ContextImpl& context, Body body) const {
    OpenMM::ReferencePlatform::PlatformData& data = *static_cast<OpenMM::ReferencePlatform::PlatformData*>(context.getPlatformData());
    Vec3 box[3];
    context.getPeriodicBoxVectors(box[0], box[1], box[2]);
    const ReferencePairList pairList(std::vector<bool>(numParticles, true), table->getMaxCutoff(), periodic, 1);
    for (const ReferencePair& p : pairList.find(*data.positions, box)) {
        const int t = table->index(p.i, p.j);
        const double r = std::sqrt(p.d.dot(p.d));
        if (r < table->cutoff(t) && exclusions.count(std::make_pair(std::min(p.i, p.j), std::max(p.i, p.j))) == 0)
            body(p, t, r);
    }
}

double ReferenceSoftRepulsionKernel::execute(OpenMM::ContextImpl& context, bool includeForces, bool includeEnergy) {
    std::vector<Vec3>& forces = *static_cast<OpenMM::ReferencePlatform::PlatformData*>(context.getPlatformData())->forces;
    double energy = 0;
    forEachPair(context, [&](const ReferencePair& p, int t, double r) {
        energy += SoftRepulsionPair::energy(table->value(t), table->cutoff(t), r);
        if (includeForces && r > 0) {
            const Vec3 f = p.d * (SoftRepulsionPair::force(table->value(t), table->inverseCutoff(t), r) / r);
            forces[p.i] += f;
            forces[p.j] -= f;
        }
    });
    return includeEnergy ? energy : 0.0;
}

std::array<double, 6> ReferenceSoftRepulsionKernel::computeVirial(OpenMM::ContextImpl& context) {
    SymmetricTensor virial{};
    forEachPair(context, [&](const ReferencePair& p, int t, double r) {
        if (r > 0)
            addAlong(virial, p.d / r, r * SoftRepulsionPair::force(table->value(t), table->inverseCutoff(t), r));
    });
    return virial;
}
