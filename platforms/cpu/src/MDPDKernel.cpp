#include "openmmdpd/MDPDKernel.h"
#include "openmmdpd/PressureTensor.h"
#include "openmmdpd/SlotAccumulation.h"
#include "openmm/internal/ContextImpl.h"
#include "ReferencePlatform.h"
#include <algorithm>

using namespace DPDPlugin;
using OpenMM::Vec3;

void MDPDKernel::initialize(const OpenMM::System& system, const MDPDForce& force) {
    numParticles = system.getNumParticles();
    periodic = force.usesPeriodicBoundaryConditions();
    excludedPairs = ExcludedPairs(numParticles, exclusionPairs(force));
    const int workers = executor->getNumWorkers();
    workerEnergy.assign(workers, 0.0);
    workerPairs.assign(workers, std::vector<Pair>());
    workerDensity.assign(workers, std::vector<double>(numParticles));
    workerForces.assign(workers, std::vector<Vec3>(numParticles));
    slotRepulsion.assign(numParticles, 0.0);
    particleRepulsion.assign(numParticles, 0.0);
    setParameters(force);
}

void MDPDKernel::copyParametersToContext(OpenMM::ContextImpl&, const MDPDForce& force) {
    setParameters(force);
}

void MDPDKernel::setParameters(const MDPDForce& force) {
    parameters.reset(new MDPDParameters(numParticles, force));
    pairSearch.reset(new PairSearch(std::vector<bool>(numParticles, true), parameters->getTable().getMaxCutoff(), periodic));
    densitySearch.reset(new PairSearch(std::vector<bool>(numParticles, true), parameters->getDensityCutoff(), periodic));
    version++;
}

void MDPDKernel::pairForces(int n, const int* first, const int* second, const int* types, const double* r, const double* valueSums,
                            double* out) const {
    const TypePairTable& table = parameters->getTable();
    for (int k = 0; k < n; k++) {
        const bool acts = r[k] < table.cutoff(types[k]) && !excludedPairs.contains(first[k], second[k]);
        out[k] = (acts ? parameters->pairForce(types[k], r[k], valueSums[k]) : 0.0);
    }
}

void MDPDKernel::sumWorkerDensities(int w, int workers) {
    std::vector<double>& density = workerDensity[w];
    densitySearch->workerSlotReach(w, workers).zero(density);
    const std::vector<int>& sortedIndex = densitySearch->getSortedIndex();
    size_t begin, end;
    densitySearch->workerCells(w, workers, begin, end);
    densitySearch->forEachSortedPairBlock((int) begin, (int) end, [&](int p, const int* q, const Vec3* d, int count) {
        double densityP = 0;
        for (int k = 0; k < count; k++) {
            if (excludedPairs.contains(sortedIndex[p], sortedIndex[q[k]]))
                continue;
            const double weight = parameters->densityWeight(std::sqrt(d[k].dot(d[k])));
            densityP += weight;
            density[q[k]] += weight;
        }
        density[p] += densityP;
    });
}

void MDPDKernel::sumDensities(OpenMM::ContextImpl& context) {
    OpenMM::ReferencePlatform::PlatformData& data = *static_cast<OpenMM::ReferencePlatform::PlatformData*>(context.getPlatformData());
    Vec3 box[3];
    context.getPeriodicBoxVectors(box[0], box[1], box[2]);
    densitySearch->build(*data.positions, box, executor.get());
    const int workers = executor->getNumWorkers();
    executor->execute([&](int w) { sumWorkerDensities(w, workers); });
    const std::vector<int>& sortedIndex = densitySearch->getSortedIndex();
    const std::vector<PairSearch::SlotReach> reach = densitySearch->workerSlotReaches(workers);
    const TypePairTable& table = parameters->getTable();
    executor->execute([&](int w) {
        size_t begin, end;
        executor->range(w, sortedIndex.size(), begin, end);
        for (size_t k = begin; k < end; k++) {
            const int i = sortedIndex[k];
            particleRepulsion[i] = parameters->typeB(table.typeOf(i)) * sumWithinReach(workerDensity, reach, k);
        }
    });
}

bool MDPDKernel::actsOn(int p, int q, double r2, int& t) const {
    const TypePairTable& table = parameters->getTable();
    t = table.indexOfTypes(sortedType[p], sortedType[q]);
    const std::vector<int>& sortedIndex = pairSearch->getSortedIndex();
    return r2 < table.cutoff2(t) && !excludedPairs.contains(sortedIndex[p], sortedIndex[q]);
}

void MDPDKernel::listPairs(int w, int workers) {
    std::vector<double>& density = workerDensity[w];
    std::vector<Pair>& pairs = workerPairs[w];
    pairs.clear();
    pairSearch->workerSlotReach(w, workers).zero(density);
    const double densityCutoff = parameters->getDensityCutoff();
    size_t begin, end;
    pairSearch->workerCells(w, workers, begin, end);
    pairSearch->forEachSortedPairBlock((int) begin, (int) end, [&](int p, const int* q, const Vec3* d, int count) {
        double densityP = 0;  // summed here, then added: the same order as the Reference's loop over p's pairs
        for (int k = 0; k < count; k++) {
            const double r2 = d[k].dot(d[k]);
            int t;
            if (!actsOn(p, q[k], r2, t))
                continue;
            const double r = std::sqrt(r2);
            pairs.push_back({p, q[k], t, r, d[k]});
            if (r < densityCutoff) {
                const double weight = parameters->densityWeight(r);
                densityP += weight;
                density[q[k]] += weight;
            }
        }
        density[p] += densityP;
    });
}

double MDPDKernel::sumPairForces(int w, int workers, bool includeEnergy) {
    std::vector<Vec3>& force = workerForces[w];
    pairSearch->workerSlotReach(w, workers).zero(force);
    double energy = 0;
    for (const Pair& pair : workerPairs[w]) {
        if (includeEnergy)
            energy += parameters->pairEnergy(pair.t, pair.r);
        if (pair.r > 0) {
            const Vec3 f = pair.d * (pairForce(pair.p, pair.q, pair.t, pair.r) / pair.r);
            force[pair.p] += f;
            force[pair.q] -= f;
        }
    }
    return energy;
}

void MDPDKernel::searchAndSumDensities(OpenMM::ContextImpl& context, bool includeEnergy) {
    OpenMM::ReferencePlatform::PlatformData& data = *static_cast<OpenMM::ReferencePlatform::PlatformData*>(context.getPlatformData());
    Vec3 box[3];
    context.getPeriodicBoxVectors(box[0], box[1], box[2]);
    pairSearch->build(*data.positions, box, executor.get());
    const std::vector<int>& sortedIndex = pairSearch->getSortedIndex();
    const size_t slots = sortedIndex.size();
    sortedType.resize(slots);
    for (size_t k = 0; k < slots; k++)
        sortedType[k] = parameters->getTable().typeOf(sortedIndex[k]);
    const int workers = executor->getNumWorkers();
    executor->execute([&](int w) { listPairs(w, workers); });
    const std::vector<PairSearch::SlotReach> reach = pairSearch->workerSlotReaches(workers);
    executor->execute([&](int w) {
        size_t begin, end;
        executor->range(w, slots, begin, end);
        double energy = 0;
        for (size_t k = begin; k < end; k++) {
            const double rho = sumWithinReach(workerDensity, reach, k);
            slotRepulsion[k] = parameters->typeB(sortedType[k]) * rho;
            if (includeEnergy)
                energy += parameters->particleEnergy(sortedType[k], rho);
        }
        workerEnergy[w] = energy;
    });
}

double MDPDKernel::execute(OpenMM::ContextImpl& context, bool includeForces, bool includeEnergy) {
    if (deferred) {
        sumDensities(context);
        return 0.0;
    }
    searchAndSumDensities(context, includeEnergy);
    const int workers = executor->getNumWorkers();
    executor->execute([&](int w) { workerEnergy[w] += sumPairForces(w, workers, includeEnergy); });
    if (includeForces) {
        std::vector<Vec3>& forces = *static_cast<OpenMM::ReferencePlatform::PlatformData*>(context.getPlatformData())->forces;
        const std::vector<int>& sortedIndex = pairSearch->getSortedIndex();
        const std::vector<PairSearch::SlotReach> reach = pairSearch->workerSlotReaches(workers);
        executor->execute([&](int w) {
            size_t begin, end;
            executor->range(w, sortedIndex.size(), begin, end);
            for (size_t k = begin; k < end; k++)
                forces[sortedIndex[k]] += sumWithinReach(workerForces, reach, k);
        });
    }
    double energy = 0;
    for (double e : workerEnergy)
        energy += e;
    return includeEnergy ? energy : 0.0;
}

std::array<double, 6> MDPDKernel::computeVirial(OpenMM::ContextImpl& context) {
    searchAndSumDensities(context, false);
    const int workers = executor->getNumWorkers();
    std::vector<SymmetricTensor> workerVirial(workers, SymmetricTensor{});
    executor->execute([&](int w) {
        SymmetricTensor sum{};  // a local: the workers' tensors share cache lines
        for (const Pair& pair : workerPairs[w])
            if (pair.r > 0)
                addAlong(sum, pair.d / pair.r, pair.r * pairForce(pair.p, pair.q, pair.t, pair.r));
        workerVirial[w] = sum;
    });
    SymmetricTensor virial{};
    for (const SymmetricTensor& v : workerVirial)
        addTensor(virial, v);
    return virial;
}
