#include "openmmdpd/ReferenceMDPDKernel.h"
#include "openmmdpd/ExcludedPairs.h"
#include "openmmdpd/PressureTensor.h"
#include "openmm/internal/ContextImpl.h"
#include "ReferencePlatform.h"
#include <algorithm>

using namespace DPDPlugin;
using OpenMM::Vec3;

void ReferenceMDPDKernel::initialize(const OpenMM::System& system, const MDPDForce& force) {
    numParticles = system.getNumParticles();
    periodic = force.usesPeriodicBoundaryConditions();
    for (const std::pair<int, int>& pair : exclusionPairs(force))
        exclusions.insert(std::minmax(pair.first, pair.second));
    parameters.reset(new MDPDParameters(numParticles, force));
}

void ReferenceMDPDKernel::copyParametersToContext(OpenMM::ContextImpl&, const MDPDForce& force) {
    parameters.reset(new MDPDParameters(numParticles, force));
}

std::vector<ReferenceMDPDKernel::Pair> ReferenceMDPDKernel::findPairs(OpenMM::ContextImpl& context,
                                                                      std::vector<double>& density) const {
    OpenMM::ReferencePlatform::PlatformData& data = *static_cast<OpenMM::ReferencePlatform::PlatformData*>(context.getPlatformData());
    Vec3 box[3];
    context.getPeriodicBoxVectors(box[0], box[1], box[2]);
    const TypePairTable& table = parameters->getTable();
    const ReferencePairList pairList(std::vector<bool>(numParticles, true), table.getMaxCutoff(), periodic, 1);
    std::vector<Pair> pairs;
    density.assign(numParticles, 0.0);
    for (const ReferencePair& p : pairList.find(*data.positions, box)) {
        const int t = table.index(p.i, p.j);
        const double r = std::sqrt(p.d.dot(p.d));
        if (r >= table.cutoff(t) || exclusions.count(std::make_pair(std::min(p.i, p.j), std::max(p.i, p.j))) != 0)
            continue;
        pairs.push_back({p, t, r});
        const double w = parameters->densityWeight(r);
        density[p.i] += w;
        density[p.j] += w;
    }
    return pairs;
}

double ReferenceMDPDKernel::pairForce(const Pair& p, const std::vector<double>& density) const {
    const TypePairTable& table = parameters->getTable();
    const double repulsion = parameters->typeB(table.typeOf(p.pair.i)) * density[p.pair.i] +
                             parameters->typeB(table.typeOf(p.pair.j)) * density[p.pair.j];
    return parameters->pairForce(p.typePair, p.r, repulsion);
}

double ReferenceMDPDKernel::execute(OpenMM::ContextImpl& context, bool includeForces, bool includeEnergy) {
    std::vector<Vec3>& forces = *static_cast<OpenMM::ReferencePlatform::PlatformData*>(context.getPlatformData())->forces;
    std::vector<double> density;
    const std::vector<Pair> pairs = findPairs(context, density);
    double energy = 0;
    for (int i = 0; i < numParticles; i++)
        energy += parameters->particleEnergy(parameters->getTable().typeOf(i), density[i]);
    for (const Pair& p : pairs) {
        energy += parameters->pairEnergy(p.typePair, p.r);
        if (includeForces && p.r > 0) {
            const Vec3 f = p.pair.d * (pairForce(p, density) / p.r);
            forces[p.pair.i] += f;
            forces[p.pair.j] -= f;
        }
    }
    return includeEnergy ? energy : 0.0;
}

std::array<double, 6> ReferenceMDPDKernel::computeVirial(OpenMM::ContextImpl& context) {
    std::vector<double> density;
    SymmetricTensor virial{};
    for (const Pair& p : findPairs(context, density))
        if (p.r > 0)
            addAlong(virial, p.pair.d / p.r, p.r * pairForce(p, density));
    return virial;
}
