#include "openmmdpd/SoftRepulsionKernel.h"
#include "openmm/internal/ContextImpl.h"
#include "ReferencePlatform.h"
#include <algorithm>

using namespace DPDPlugin;
using OpenMM::Vec3;

void SoftRepulsionKernel::initialize(const OpenMM::System& system, const DPDSoftRepulsionForce& force) {
    numParticles = system.getNumParticles();
    periodic = force.usesPeriodicBoundaryConditions();
    exclusions.assign(numParticles, std::vector<int>());
    for (int k = 0; k < force.getNumExclusions(); k++) {
        int p1, p2;
        force.getExclusionParticles(k, p1, p2);
        exclusions[p1].push_back(p2);
        exclusions[p2].push_back(p1);
    }
    for (auto& partners : exclusions)
        std::sort(partners.begin(), partners.end());
    const int workers = executor->getNumWorkers();
    workerEnergy.assign(workers, 0.0);
    workerForces.assign(workers, std::vector<Vec3>(numParticles));
    setParameters(force);
}

void SoftRepulsionKernel::copyParametersToContext(OpenMM::ContextImpl&, const DPDSoftRepulsionForce& force) {
    setParameters(force);
}

void SoftRepulsionKernel::setParameters(const DPDSoftRepulsionForce& force) {
    std::vector<TypePairTable::Entry> entries(force.getNumTypePairs());
    for (int k = 0; k < force.getNumTypePairs(); k++) {
        TypePairTable::Entry& e = entries[k];
        force.getTypePairParameters(k, e.type1, e.type2, e.value, e.cutoff);
    }
    table.reset(new TypePairTable(numParticles, force.getParticleTypes(), force.getDefaultA(), force.getDefaultCutoff(), entries));
    search.reset(new PairSearch(std::vector<bool>(numParticles, true), table->getMaxCutoff(), periodic));
    version++;
}

double SoftRepulsionKernel::execute(OpenMM::ContextImpl& context, bool includeForces, bool includeEnergy) {
    if (deferred)
        return 0.0;
    OpenMM::ReferencePlatform::PlatformData& data = *static_cast<OpenMM::ReferencePlatform::PlatformData*>(context.getPlatformData());
    std::vector<Vec3>& forces = *data.forces;
    Vec3 box[3];
    context.getPeriodicBoxVectors(box[0], box[1], box[2]);
    search->build(*data.positions, box);
    const int workers = executor->getNumWorkers();
    executor->execute([&](int w) {
        // One worker adds straight into the Context's forces; several use their own buffers.
        const bool direct = (workers == 1 && includeForces);
        std::vector<Vec3>& out = (direct ? forces : workerForces[w]);
        if (!direct)
            std::fill(out.begin(), out.end(), Vec3());
        double energy = 0;
        size_t begin, end;
        search->workerCells(w, workers, begin, end);
        search->forEachPair((int) begin, (int) end, [&](int i, int j, const Vec3& d) {
            const int t = table->index(i, j);
            const double r2 = d.dot(d);
            if (r2 >= table->cutoff2(t) || excluded(i, j))
                return;
            const double r = std::sqrt(r2), rc = table->cutoff(t), a = table->value(t);
            const double x = 1 - r / rc;
            // F = a (1 - r/rc) e;  E = a rc (1 - r/rc)^2 / 2
            if (r > 0) {
                const Vec3 f = d * (a * x / r);
                out[i] += f;
                out[j] -= f;
            }
            energy += 0.5 * a * rc * x * x;
        });
        workerEnergy[w] = energy;
    });
    if (workers > 1 && includeForces)
        executor->execute([&](int w) {
            size_t begin, end;
            executor->range(w, forces.size(), begin, end);
            for (size_t i = begin; i < end; i++)
                for (int k = 0; k < workers; k++)
                    forces[i] += workerForces[k][i];
        });
    double energy = 0;
    for (double e : workerEnergy)
        energy += e;
    return includeEnergy ? energy : 0.0;
}
