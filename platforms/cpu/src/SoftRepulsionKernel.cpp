#include "openmmdpd/SoftRepulsionKernel.h"
#include "openmmdpd/SlotAccumulation.h"
#include "openmmdpd/PressureTensor.h"
#include "openmm/internal/ContextImpl.h"
#include "ReferencePlatform.h"
#include <algorithm>

using namespace DPDPlugin;
using OpenMM::Vec3;

void SoftRepulsionKernel::initialize(const OpenMM::System& system, const DPDSoftRepulsionForce& force) {
    numParticles = system.getNumParticles();
    periodic = force.usesPeriodicBoundaryConditions();
    excludedPairs = ExcludedPairs(numParticles, exclusionPairs(force));
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
    pairSearch.reset(new PairSearch(std::vector<bool>(numParticles, true), table->getMaxCutoff(), periodic));
    version++;
}

void SoftRepulsionKernel::search(OpenMM::ContextImpl& context) {
    OpenMM::ReferencePlatform::PlatformData& data = *static_cast<OpenMM::ReferencePlatform::PlatformData*>(context.getPlatformData());
    Vec3 box[3];
    context.getPeriodicBoxVectors(box[0], box[1], box[2]);
    pairSearch->build(*data.positions, box, executor.get());
    const std::vector<int>& sortedIndex = pairSearch->getSortedIndex();
    sortedType.resize(sortedIndex.size());
    for (size_t k = 0; k < sortedIndex.size(); k++)
        sortedType[k] = table->typeOf(sortedIndex[k]);
}

double SoftRepulsionKernel::execute(OpenMM::ContextImpl& context, bool includeForces, bool includeEnergy) {
    if (deferred)
        return 0.0;
    search(context);
    const std::vector<int>& sortedIndex = pairSearch->getSortedIndex();
    const size_t slots = sortedIndex.size();
    const int workers = executor->getNumWorkers();
    // Each worker sums its cells' pairs into its own buffer, by sorted slot; the buffers are
    // then added to the Context's forces in worker order.
    executor->execute([&](int w) {
        double energy = 0;
        auto evaluate = [&](int p, const int* q, const Vec3* d, int count, int* slots, Vec3* pairForces) {
            int n = 0;
            for (int k = 0; k < count; k++) {
                const double r2 = d[k].dot(d[k]);
                int t;
                if (!actsOn(p, q[k], r2, t))
                    continue;
                const double a = table->value(t), r = std::sqrt(r2);
                if (includeEnergy)
                    energy += SoftRepulsionPair::energy(a, table->cutoff(t), r);
                if (r2 > 0) {
                    slots[n] = q[k];
                    pairForces[n++] = d[k] * (SoftRepulsionPair::force(a, table->inverseCutoff(t), r) / r);
                }
            }
            return n;
        };
        accumulateBySlot(*pairSearch, w, workers, evaluate, workerForces[w]);
        workerEnergy[w] = energy;
    });
    if (includeForces) {
        std::vector<Vec3>& forces = *static_cast<OpenMM::ReferencePlatform::PlatformData*>(context.getPlatformData())->forces;
        const std::vector<PairSearch::SlotReach> reach = pairSearch->workerSlotReaches(workers);
        executor->execute([&](int w) {
            size_t begin, end;
            executor->range(w, slots, begin, end);
            for (size_t k = begin; k < end; k++) {
                const Vec3 f = sumWithinReach(workerForces, reach, k);
                prefetchSlotParticle(forces.data(), sortedIndex, k);
                forces[sortedIndex[k]] += f;
            }
        });
    }
    double energy = 0;
    for (double e : workerEnergy)
        energy += e;
    return includeEnergy ? energy : 0.0;
}

std::array<double, 6> SoftRepulsionKernel::computeVirial(OpenMM::ContextImpl& context) {
    search(context);
    const int workers = executor->getNumWorkers();
    std::vector<SymmetricTensor> workerVirial(workers, SymmetricTensor{});
    executor->execute([&](int w) {
        size_t begin, end;
        pairSearch->workerCells(w, workers, begin, end);
        SymmetricTensor sum{};  // a local: the workers' tensors share cache lines
        pairSearch->forEachSortedPairBlock((int) begin, (int) end, [&](int p, const int* q, const Vec3* d, int count) {
            for (int k = 0; k < count; k++) {
                const double r2 = d[k].dot(d[k]);
                int t;
                if (r2 > 0 && actsOn(p, q[k], r2, t)) {
                    const double r = std::sqrt(r2);
                    addAlong(sum, d[k] / r, r * SoftRepulsionPair::force(table->value(t), table->inverseCutoff(t), r));
                }
            }
        });
        workerVirial[w] = sum;
    });
    SymmetricTensor virial{};
    for (const SymmetricTensor& v : workerVirial)
        addTensor(virial, v);
    return virial;
}
