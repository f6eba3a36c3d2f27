#include "openmmdpd/DPDThermostatForces.h"
#include "openmmdpd/DPDPairRows.h"
#include "openmmdpd/PairRandomBatch.h"
#include "openmmdpd/SlotAccumulation.h"
#include "openmmdpd/SoftRepulsionKernel.h"
#include "openmmdpd/FusedPairForce.h"
#include "openmmdpd/UniformPairBlock.h"
#include "openmmdpd/internal/ParameterChecks.h"
#include "openmm/OpenMMException.h"
#include <algorithm>
#include <array>
#include <memory>

using namespace DPDPlugin;
using OpenMM::Vec3;

namespace {

void zero(std::vector<Vec3>& v, size_t begin, size_t end) {
    for (size_t i = begin; i < end; i++)
        v[i] = Vec3();
}

} // namespace

DPDThermostatForces::DPDThermostatForces(const OpenMM::System& system, const DPDThermostatIntegrator& integrator,
                                         ParallelExecutor& executor, int cellMultiple) :
        name(integrator.className()), parameters(system, integrator), executor(executor),
        search(parameters.getActive(), parameters.getMaxCutoff(), system.usesPeriodicBoundaryConditions(), cellMultiple),
        cellMultiple(cellMultiple), random(PairRandom::seedFor(integrator.getRandomNumberSeed())) {
    const int workers = executor.getNumWorkers();
    workerPairs.resize(workers);
    workerUniformPairs.resize(workers);
    workerPairParticles.resize(workers);
    workerListSize.resize(workers);
    keptPairs.resize(workers);
    keptImageVx.resize(workers);
    keptTransverseGammaWD.resize(workers);
    keptPairCount.assign(workers, 0);
    workerDissipative.assign(workers, std::vector<Vec3>(system.getNumParticles()));
    if (workers > 1)
        workerRandom.assign(workers, std::vector<Vec3>(system.getNumParticles()));
}

void DPDThermostatForces::setParameters(const OpenMM::System& system, const DPDThermostatIntegrator& integrator) {
    parameters = DPDPairParameters(system, integrator);
    search = PairSearch(parameters.getActive(), parameters.getMaxCutoff(), system.usesPeriodicBoundaryConditions(), cellMultiple);
}

void DPDThermostatForces::checkCutoffFitsBox(const Vec3* box) const {
    if (search.isPeriodic())
        requireCutoffFitsBox(name, "the thermostat cutoff", parameters.getMaxCutoff(), box);
}

void DPDThermostatForces::updatePairs(const std::vector<Vec3>& positions, const Vec3* box, const FusedPairForce* fused,
                                      std::vector<Vec3>* fusedOut, bool bySlot) {
    checkCutoffFitsBox(box);
    pairsBySlot = bySlot;
    search.build(positions, box, &executor);
    workerReach = search.workerSlotReaches(executor.getNumWorkers());
    searched = &positions;
    searchedHeight = box[1][1];
    cellPairStart.resize(search.getNumCells() + 1);
    cellPairs.resize(search.getNumCells());
    pairsUniform = (bySlot && canRunUniformPairBlock() && (uniformRule(fused, listRule) || uniformRule(nullptr, listRule)));
    cellUniformPairs.resize(search.getNumCells());
    const std::vector<int>& sortedIndex = search.getSortedIndex();
    const bool sheared = (parameters.getShearRate() != 0);
    sortedTypes.resize(sortedIndex.size());
    sortedHeights.resize(sheared ? sortedIndex.size() : 0);
    sortedFusedTypes.resize(fused != nullptr ? sortedIndex.size() : sortedFusedTypes.size());
    sortedFusedValues.resize(fused != nullptr && fused->getParticleValues() != nullptr ? sortedIndex.size() : sortedFusedValues.size());
    slotsSorted = true;
    fusedSorted = (fused != nullptr);
    sortedFused = fused;
    if (fused != nullptr && sortedIndex.size() < fusedOut->size())
        std::fill(fusedOut->begin(), fusedOut->end(), Vec3());
    // Cell ranges in order, concatenated in order: the same pairs in the same order for any
    // number of workers.  Worker 0 writes the start of the list itself; by particle, the
    // other workers' parts are copied in after it, every worker copying an equal share (the
    // list is ~15 MB at N = 32000: copied by one thread it would be a serial part of every
    // step); by slot they stay apart, for the sweeps, which take each cell's pairs from
    // where they lie.  The fused force is summed by slot, as in sumBySlot.  One dispatch.
    const int workers = executor.getNumWorkers();
    pairsInParts = (bySlot && workers > 1);
    executor.executePhases(4, [&](int w, int phase) {
        size_t begin, end;
        executor.range(w, sortedIndex.size(), begin, end);
        if (phase == 0) {
            sortTypes(begin, end, sheared);
            if (fused != nullptr)
                sortFusedTypes(begin, end, *fused);
        }
        else if (phase == 1)
            findWorkerPairs(w, fused);
        else if (phase == 2 && w == 0 && !pairsInParts) {
            if (pairsUniform)
                sizeForWorkerLists(uniformPairs);
            else
                sizeForWorkerLists(pairs);
            sizeForWorkerLists(pairParticles);
        }
        else if (phase == 3) {
            if (workers > 1 && !pairsInParts) {
                copyWorkerLists(w, workerPairs, pairs);
                copyWorkerLists(w, workerPairParticles, pairParticles);
            }
            placeWorkerCells(w);
            for (size_t k = begin; fused != nullptr && k < end; k++) {
                prefetchSlotParticle(fusedOut->data(), sortedIndex, k);
                (*fusedOut)[sortedIndex[k]] = sumWithinReach(workerDissipative, workerReach, k);
            }
        }
    });
    cellPairStart[search.getNumCells()] = (int) workerPairsBefore(workers);
}

const std::vector<PairGeometry>& DPDThermostatForces::getPairs() const {
    if (pairsInParts || pairsUniform)
        throw OpenMM::OpenMMException(name + ": internal error: the pair list found by slot is in the workers' parts or of UniformPair; walk it by cell");
    return pairs;
}

void DPDThermostatForces::findWorkerPairs(int w, const FusedPairForce* fused) {
    if (pairsUniform) {
        fillWorkerList(w, fused, uniformPairs, workerUniformPairs,
                       [&](int p, const int* qs, const Vec3* ds, int hits, std::vector<UniformPair>& out,
                           std::vector<PairParticles>& outParticles, size_t& count, std::vector<Vec3>& fusedForce) {
                           appendUniformPairs(listRule, p, qs, ds, hits, out, outParticles, count, fusedForce,
                                              listRule.soft ? nullptr : fused);
                       });
        return;
    }
    UniformPairRule rule;
    const bool uniform = uniformRule(fused, rule) || uniformRule(nullptr, rule);
    const FusedPairForce* fusedAfter = (uniform && !rule.soft ? fused : nullptr);  // where the rows do not make it
    // The soft force inline, pair by pair: gathered into blocks for the fused force's virtual
    // call, it cost a sheared step 5-8 %.
    const SoftRepulsionKernel* soft = dynamic_cast<const SoftRepulsionKernel*>(fused);
    fillWorkerList(w, fused, pairs, workerPairs,
                   [&](int p, const int* qs, const Vec3* ds, int hits, std::vector<PairGeometry>& out,
                       std::vector<PairParticles>& outParticles, size_t& count, std::vector<Vec3>& fusedForce) {
                       if (!(uniform && appendUniformPairs(rule, p, qs, ds, hits, out, outParticles, count, fusedForce, fusedAfter)))
                           appendPairsOneByOne(p, qs, ds, hits, out, outParticles, count, fusedForce, fused, soft);
                   });
}

template <class Entry, class AppendBlock>
void DPDThermostatForces::fillWorkerList(int w, const FusedPairForce* fused, std::vector<Entry>& firstPart,
                                         std::vector<std::vector<Entry>>& otherParts, AppendBlock appendBlock) {
    size_t begin, end;
    search.workerCells(w, executor.getNumWorkers(), begin, end);
    // Worker 0 writes the list itself (with one worker, all of it): a second buffer for its
    // part would add that much memory and copying.  The lists grow in vectors of the
    // worker's own, swapped in and out: the workers' vectors sit side by side in one cache
    // line, and growing them there made every pair write a line that the other workers'
    // cores were writing too (with two threads this pass took 2.5 times its one-thread time
    // per thread).  They are overwritten from the start and keep their length (worker 0's,
    // found by particle: the whole list's, from the step before): cleared, they would be filled with zeros
    // again as they grew (a PairGeometry zeroes itself), and sizeForWorkerLists, run by
    // worker 0 alone while the others wait, would zero the other workers' part of the list.
    std::vector<Entry>& list = (w == 0 ? firstPart : otherParts[w]);
    std::vector<PairParticles>& listParticles = (w == 0 ? pairParticles : workerPairParticles[w]);
    std::vector<Entry> out;
    std::vector<PairParticles> outParticles;
    out.swap(list);
    outParticles.swap(listParticles);
    size_t count = 0;
    std::vector<Vec3>& fusedForce = workerDissipative[w];
    if (fused != nullptr)
        workerReach[w].zero(fusedForce);
    // Each cell's pairs start at a local offset, made global (and pointed to) by placeWorkerCells.
    const auto startCell = [&](int cell) { cellPairStart[cell] = (int) count; };
    search.forEachSortedPairBlock((int) begin, (int) end, [&](int p, const int* qs, const Vec3* ds, int hits) {
        appendBlock(p, qs, ds, hits, out, outParticles, count, fusedForce);
    }, startCell);
    workerListSize[w] = count;
    out.swap(list);
    outParticles.swap(listParticles);
}

void DPDThermostatForces::appendPairsOneByOne(int p, const int* qs, const Vec3* ds, int hits, std::vector<PairGeometry>& out,
                                              std::vector<PairParticles>& outParticles, size_t& count, std::vector<Vec3>& fusedForce,
                                              const FusedPairForce* fused, const SoftRepulsionKernel* soft) const {
    const std::vector<int>& sortedIndex = search.getSortedIndex();
    const TypePairTable& table = parameters.getTable();
    const size_t start = count;
    int acceptedQ[PairSearch::MAX_BLOCK];
    double r[PairSearch::MAX_BLOCK];
    for (int k = 0; k < hits; k++) {
        const int q = qs[k];
        const Vec3& d = ds[k];
        const int i = sortedIndex[p], j = sortedIndex[q], t = table.indexOfTypes(sortedTypes[p], sortedTypes[q]);
        const double imageVx =
                sortedHeights.empty() ? 0.0 : parameters.imageVelocityX(sortedHeights[p] - sortedHeights[q], d[1], searchedHeight);
        // Written in place: copied from a local, the fields stored one by one and read
        // back two at a time would stall the copy (no store forwarding).
        if (count == out.size()) {
            out.emplace_back();
            outParticles.emplace_back();
        }
        PairGeometry& g = out[count];
        if (!parameters.pairGeometry(i, j, t, d, g, imageVx))
            continue;
        const double distance = table.cutoff(t) * (1 - g.wR);
        acceptedQ[count - start] = q;
        r[count - start] = distance;
        outParticles[count++] = {i, j};
        if (pairsBySlot) {
            g.i = p;
            g.j = q;
        }
        if (soft != nullptr) {
            const int softType = soft->getTable().indexOfTypes(sortedFusedTypes[p], sortedFusedTypes[q]);
            const Vec3 f = g.e * soft->pairForce(i, j, softType, distance);
            fusedForce[p] += f;
            fusedForce[q] -= f;
        }
    }
    if (fused != nullptr && soft == nullptr && count > start)
        addFusedForces(*fused, p, acceptedQ, &out[start], r, (int) (count - start), fusedForce);
}

template <class Entry>
bool DPDThermostatForces::appendUniformPairs(const UniformPairRule& rule, int p, const int* qs, const Vec3* ds, int hits,
                                             std::vector<Entry>& out, std::vector<PairParticles>& outParticles, size_t& count,
                                             std::vector<Vec3>& fusedForce, const FusedPairForce* fused) const {
    if (count + hits > out.size()) {
        out.resize(count + hits);
        outParticles.resize(count + hits);
    }
    int acceptedQ[PairSearch::MAX_BLOCK];
    const int n = uniformPairBlock(rule, p, qs, ds, hits, acceptedQ, &out[count], fusedForce.data());
    if (n > 0 && fused != nullptr) {
        double r[PairSearch::MAX_BLOCK];
        for (int k = 0; k < n; k++)
            r[k] = rule.cutoff * (1 - out[count + k].wR);
        addFusedForces(*fused, p, acceptedQ, &out[count], r, n, fusedForce);
    }
    const std::vector<int>& sortedIndex = search.getSortedIndex();
    for (int k = 0; k < n; k++, count++) {
        const int q = acceptedQ[k], i = sortedIndex[p], j = sortedIndex[q];
        out[count].i = (pairsBySlot ? p : i);
        out[count].j = (pairsBySlot ? q : j);
        outParticles[count] = {i, j};
    }
    return n >= 0;
}

template <class Entry>
void DPDThermostatForces::addFusedForces(const FusedPairForce& fused, int p, const int* acceptedQ, const Entry* accepted, const double* r,
                                         int n, std::vector<Vec3>& fusedForce) const {
    const std::vector<int>& sortedIndex = search.getSortedIndex();
    const TypePairTable& table = fused.getTable();
    const bool values = (fused.getParticleValues() != nullptr);
    int first[PairSearch::MAX_BLOCK], second[PairSearch::MAX_BLOCK], types[PairSearch::MAX_BLOCK];
    double valueSums[PairSearch::MAX_BLOCK], along[PairSearch::MAX_BLOCK];
    const int i = sortedIndex[p], typeP = sortedFusedTypes[p];
    for (int k = 0; k < n; k++) {
        const int q = acceptedQ[k];
        first[k] = i;
        second[k] = sortedIndex[q];
        types[k] = table.indexOfTypes(typeP, sortedFusedTypes[q]);
    }
    for (int k = 0; values && k < n; k++)
        valueSums[k] = sortedFusedValues[p] + sortedFusedValues[acceptedQ[k]];
    fused.pairForces(n, first, second, types, r, values ? valueSums : nullptr, along);
    for (int k = 0; k < n; k++) {
        const Vec3 f = accepted[k].e * along[k];
        fusedForce[p] += f;
        fusedForce[acceptedQ[k]] -= f;
    }
}

bool DPDThermostatForces::uniformRule(const FusedPairForce* fused, UniformPairRule& rule) const {
    const TypePairTable& table = parameters.getTable();
    if (table.getNumTypes() != 1 || !table.hasStandardWeights() || parameters.hasExceptions() || !parameters.hasUniformMass() ||
        parameters.getShearRate() != 0 || parameters.hasTransverse())
        return false;
    if (fused != nullptr && !fused->isUniformSoftRepulsion())
        return false;
    rule = {table.cutoff(0), table.cutoff2(0), parameters.uniformGamma(0), parameters.uniformSigma(0), table.value(0), fused != nullptr,
            fused ? fused->getTable().value(0) : 0.0, fused ? fused->getTable().inverseCutoff(0) : 0.0, fused ? fused->getTable().cutoff(0) : 0.0};
    return true;
}

template <class Entry>
void DPDThermostatForces::sizeForWorkerLists(std::vector<Entry>& list) const {
    list.resize(workerPairsBefore(executor.getNumWorkers()));
}

template <class Entry>
void DPDThermostatForces::copyWorkerLists(int w, const std::vector<std::vector<Entry>>& workerLists, std::vector<Entry>& list) const {
    // Worker w's share [begin, end) of the entries after worker 0's, wherever they come from.
    const size_t first = workerListSize[0];
    size_t begin, end;
    executor.range(w, list.size() - first, begin, end);
    for (int v = 1; v < executor.getNumWorkers(); v++) {
        const size_t start = workerPairsBefore(v) - first, from = std::max(begin, start),
                     to = std::min(end, start + workerListSize[v]);
        if (from < to)
            std::copy(workerLists[v].begin() + (from - start), workerLists[v].begin() + (to - start), list.begin() + first + from);
    }
}

size_t DPDThermostatForces::workerPairsBefore(int w) const {
    size_t total = 0;
    for (int v = 0; v < w; v++)
        total += workerListSize[v];
    return total;
}

void DPDThermostatForces::placeWorkerCells(int w) {
    size_t begin, end;
    search.workerCells(w, executor.getNumWorkers(), begin, end);
    const size_t offset = workerPairsBefore(w);
    if (pairsUniform)
        pointCellsInto(w, begin, end, offset, uniformPairs, workerUniformPairs, cellUniformPairs);
    else
        pointCellsInto(w, begin, end, offset, pairs, workerPairs, cellPairs);
    for (size_t cell = begin; cell < end; cell++)
        cellPairStart[cell] += (int) offset;
}

template <class Entry>
void DPDThermostatForces::pointCellsInto(int w, size_t begin, size_t end, size_t offset, const std::vector<Entry>& firstPart,
                                         const std::vector<std::vector<Entry>>& otherParts, std::vector<const Entry*>& cellEntries) {
    const Entry* part = (pairsInParts ? (w == 0 ? firstPart : otherParts[w]).data() : firstPart.data() + offset);
    for (size_t cell = begin; cell < end; cell++)
        cellEntries[cell] = part + cellPairStart[cell];
}

void DPDThermostatForces::compute(int terms, const std::vector<Vec3>& velocities, long long step, double dt,
                                  std::vector<Vec3>& dissipative, std::vector<Vec3>& randomForce) {
    const std::vector<PairGeometry>& list = getPairs();
    const double invSqrtDt = 1 / std::sqrt(dt);
    const bool both = (terms & DissipativeTerm) && (terms & RandomTerm);
    if (both && &dissipative == &randomForce)
        sumOverPairs(DPDListForces<true, true, false>{list, velocities, random, step, invSqrtDt}, {&dissipative});
    else if (both)
        sumOverPairs(DPDListForces<true, true, true>{list, velocities, random, step, invSqrtDt}, {&dissipative, &randomForce});
    else if (terms & DissipativeTerm)
        sumOverPairs(DPDListForces<true, false, false>{list, velocities, random, step, invSqrtDt}, {&dissipative});
    else if (terms & RandomTerm)
        sumOverPairs(DPDListForces<false, true, false>{list, velocities, random, step, invSqrtDt}, {&randomForce});
}

void DPDThermostatForces::addVirial(int terms, const std::vector<Vec3>& velocities, long long step, double dt,
                                    SymmetricTensor& virial) {
    const std::vector<PairGeometry>& list = getPairs();
    const double invSqrtDt = 1 / std::sqrt(dt);
    std::vector<SymmetricTensor> workerVirial(executor.getNumWorkers(), SymmetricTensor{});
    executor.execute([&](int w) {
        size_t begin, end;
        executor.range(w, list.size(), begin, end);
        if (terms == (DissipativeTerm | RandomTerm))
            addVirialAlongPairs(list, begin, end, DPDListForces<true, true, false>{list, velocities, random, step, invSqrtDt},
                                parameters, workerVirial[w]);
        else if (terms == DissipativeTerm)
            addVirialAlongPairs(list, begin, end, DPDListForces<true, false, false>{list, velocities, random, step, invSqrtDt},
                                parameters, workerVirial[w]);
        else
            addVirialAlongPairs(list, begin, end, DPDListForces<false, true, false>{list, velocities, random, step, invSqrtDt},
                                parameters, workerVirial[w]);
    });
    for (const SymmetricTensor& t : workerVirial)
        addTensor(virial, t);
}

template <class Evaluator>
void DPDThermostatForces::sumOverPairs(const Evaluator& evaluator, std::array<std::vector<Vec3>*, Evaluator::OUTPUTS> out) {
    const std::vector<PairGeometry>& list = getPairs();
    const int workers = executor.getNumWorkers();
    if (workers == 1) {
        for (std::vector<Vec3>* o : out)
            zero(*o, 0, o->size());
        accumulateAlongPairs(list, 0, list.size(), evaluator, out.data());
        return;
    }
    // Each worker sums its pair range into its own buffers; then each worker reduces a
    // particle range over all buffers, always in worker order.  One dispatch.
    executor.executePhases(2, [&](int w, int phase) {
        std::vector<std::vector<Vec3>>* buffers[2] = {&workerDissipative, &workerRandom};
        if (phase == 1) {
            for (int t = 0; t < Evaluator::OUTPUTS; t++)
                reduceWorkerBuffers(w, *buffers[t], *out[t]);
            return;
        }
        std::vector<Vec3>* own[2] = {&workerDissipative[w], workerRandom.empty() ? nullptr : &workerRandom[w]};
        for (int t = 0; t < Evaluator::OUTPUTS; t++)
            zero(*own[t], 0, out[t]->size());
        size_t begin, end;
        executor.range(w, list.size(), begin, end);
        accumulateAlongPairs(list, begin, end, evaluator, own);
    });
}

void DPDThermostatForces::reduceWorkerBuffers(int w, const std::vector<std::vector<Vec3>>& buffers, std::vector<Vec3>& out) const {
    size_t begin, end;
    executor.range(w, out.size(), begin, end);
    for (size_t i = begin; i < end; i++)
        out[i] = sumOverWorkers(buffers, i);
}

void DPDThermostatForces::sumAlongPairs(const std::vector<double>& c, std::vector<Vec3>& out) {
    sumOverPairs(PairCoefficientForces{c}, {&out});
}

void DPDThermostatForces::computeInOnePass(const std::vector<Vec3>& positions, const Vec3* box, const std::vector<Vec3>& velocities,
                                           long long step, double dt, const FusedPairForce* fused,
                                           const std::vector<Vec3>* base, std::vector<Vec3>& out) {
    searchSlots(positions, box);
    sumBySlot(DissipativeTerm | RandomTerm, velocities, step, dt, fused, base, out);
}

void DPDThermostatForces::searchSlots(const std::vector<Vec3>& positions, const Vec3* box) {
    checkCutoffFitsBox(box);
    search.build(positions, box, &executor);
    workerReach = search.workerSlotReaches(executor.getNumWorkers());
    searched = &positions;
    searchedHeight = box[1][1];
    slotsSorted = fusedSorted = false;
}

void DPDThermostatForces::sumBySlot(int terms, const std::vector<Vec3>& velocities, long long step, double dt,
                                    const FusedPairForce* fused, const std::vector<Vec3>* base, std::vector<Vec3>& out,
                                    std::vector<Vec3>* dissipativeOut, PairSource source, Indexing velocityIndexing, Indexing outputIndexing) {
    const std::vector<int>& sortedIndex = search.getSortedIndex();
    const bool velocitiesBySlot = (velocityIndexing == BySlot), bySlot = (outputIndexing == BySlot);
    const bool sheared = (parameters.getShearRate() != 0), sortTypesNow = !slotsSorted;
    const FusedPairForce* sortFused = (fused != nullptr && (!fusedSorted || fused != sortedFused) ? fused : nullptr);
    if (!velocitiesBySlot)
        sortedVelocities.resize(sortedIndex.size());
    slotVelocities = (velocitiesBySlot ? &velocities : &sortedVelocities);
    sortedHeights.resize(sheared ? sortedIndex.size() : 0);
    sortedTypes.resize(sortedIndex.size());
    sortedFusedTypes.resize(fused != nullptr ? sortedIndex.size() : sortedFusedTypes.size());
    sortedFusedValues.resize(fused != nullptr && fused->getParticleValues() != nullptr ? sortedIndex.size() : sortedFusedValues.size());
    slotsSorted = true;
    fusedSorted = fusedSorted || fused != nullptr;
    sortedFused = (fused != nullptr ? fused : sortedFused);
    if (dissipativeOut != nullptr) {
        workerRandom.resize(executor.getNumWorkers());
        for (std::vector<Vec3>& buffer : workerRandom)
            buffer.resize(out.size());
    }
    if (!bySlot && sortedIndex.size() < out.size())  // particles outside the thermostat get no pair force
        for (size_t i = 0; i < out.size(); i++) {
            out[i] = (base != nullptr ? (*base)[i] : Vec3());
            if (dissipativeOut != nullptr)
                (*dissipativeOut)[i] = Vec3();
        }
    // Three phases in one dispatch (waking a thread pool costs tens of microseconds):
    // velocities (and after a search the types) by slot; each worker's cells' pairs summed
    // into its own buffers, by slot (neighbouring pairs touch neighbouring slots); the
    // buffers added in worker order.
    executor.executePhases(3, [&](int w, int phase) {
        size_t begin, end;
        executor.range(w, sortedIndex.size(), begin, end);
        if (phase == 0) {
            if (!velocitiesBySlot)
                for (size_t k = begin; k < end; k++) {
                    prefetchSlotParticle(velocities.data(), sortedIndex, k);
                    sortedVelocities[k] = velocities[sortedIndex[k]];
                }
            if (sortTypesNow)
                sortTypes(begin, end, sheared);
            if (sortFused != nullptr)
                sortFusedTypes(begin, end, *sortFused);
        }
        else if (phase == 1 && source == KeptPairs)
            sumKeptDissipative(w);
        else if (phase == 1)
            sumPairForcesBySlot(w, terms, dissipativeOut != nullptr, fused, step, dt, source == FindAndKeepPairs);
        else
            for (size_t k = begin; k < end; k++) {
                if (!bySlot)
                    prefetchSlotParticle(out.data(), sortedIndex, k);
                if (base != nullptr)
                    prefetchSlotParticle(base->data(), sortedIndex, k);
                const int i = sortedIndex[k];
                const size_t to = (bySlot ? k : i);
                out[to] = sumWithinReach(workerDissipative, workerReach, k) + (base != nullptr ? (*base)[i] : Vec3());
                if (dissipativeOut != nullptr)
                    (*dissipativeOut)[to] = sumWithinReach(workerRandom, workerReach, k);
            }
    });
}

void DPDThermostatForces::sortFusedTypes(size_t begin, size_t end, const FusedPairForce& fused) {
    const std::vector<int>& sortedIndex = search.getSortedIndex();
    for (size_t k = begin; k < end; k++)
        sortedFusedTypes[k] = fused.getTable().typeOf(sortedIndex[k]);
    const double* values = fused.getParticleValues();
    for (size_t k = begin; values != nullptr && k < end; k++) {
        prefetchSlotParticle(values, sortedIndex, k);
        sortedFusedValues[k] = values[sortedIndex[k]];
    }
}

void DPDThermostatForces::sortTypes(size_t begin, size_t end, bool heights) {
    const std::vector<int>& sortedIndex = search.getSortedIndex();
    for (size_t k = begin; k < end; k++)
        sortedTypes[k] = parameters.getTable().typeOf(sortedIndex[k]);
    if (heights)
        for (size_t k = begin; k < end; k++)
            sortedHeights[k] = (*searched)[sortedIndex[k]][1];
}

namespace {

/**
 * FD(v) and/or FR (per `terms`; + the fused force, if given) of the pairs within their
 * thermostat cutoff, summed, or with FD as a second output (separate).  The pairs are kept
 * block by block and their forces made for the whole batch (accumulateBySlot), so that the
 * random numbers are drawn many at a time.  One per worker: its scratch arrays are set up
 * once, not per block (a Vec3 zeroes itself).
 */
struct DPDSlotForces {
    const DPDPairParameters& parameters;
    const PairRandom& random;
    const std::vector<int>& sortedIndex;
    const std::vector<Vec3>& sortedVelocities;
    const std::vector<int>& sortedTypes;      // the thermostat's type of each slot's particle
    const std::vector<int>& sortedFusedTypes;  // the fused force's (with fused only)
    const double* sortedFusedValues;           // its particle values by slot (null where it has none)
    const double* sortedHeights;  // null without shear
    double boxHeight;
    const FusedPairForce* fused;
    std::vector<DPDThermostatForces::KeptPair>* keep;  // where the accepted pairs go (null: nowhere)
    std::vector<double>* keepImageVx;                  // and their image velocities (null: nowhere)
    std::vector<double>* keepTransverse;               // and their transverse gamma wD (null: nowhere)
    int terms;
    bool separate;
    long long step;
    double invSqrtDt;
    bool transverse;  // whether any pair has transverse friction (the rows have none)
    int batchSize = 0;  // pairs in the batch so far: accumulateBySlot's position in it
    size_t keptCount = 0;  // pairs kept so far: the vectors may be longer
    PairGeometry g[PairSearch::MAX_BLOCK];
    int slotP[PairSearch::MAX_BLOCK], first[PairSearch::MAX_BLOCK], second[PairSearch::MAX_BLOCK];
    double xi[PairSearch::MAX_BLOCK], cutoff[PairSearch::MAX_BLOCK];
    double zeta[3 * PairSearch::MAX_BLOCK];  // transverse friction's noise vectors
    double fusedOnPair[PairSearch::MAX_BLOCK];  // the fused force along e (from the rows, where they make it: their softPairForce)
    int fusedTypes[PairSearch::MAX_BLOCK];     // the fused force's type pair and distance of each pair
    double distance[PairSearch::MAX_BLOCK], valueSums[PairSearch::MAX_BLOCK];

    // Every pair's parameters where they are shared, else null; the fused force's too where
    // uniform->soft (the rows then make its pair forces), else it is looked up pair by pair.
    // Set only where the rows run (canRunUniformPairBlock), so every block comes from them.
    const UniformPairRule* uniform = nullptr;

    int operator()(int p, const int* q, const Vec3* d, int count, int* slots, Vec3*) {
        const int i = sortedIndex[p], start = batchSize;
        const TypePairTable& table = parameters.getTable();
        const int n = (uniform ? uniformPairBlock(*uniform, p, q, d, count, slots, &g[batchSize], nullptr,
                                                  uniform->soft ? &fusedOnPair[batchSize] : nullptr)
                               : -1);
        if (n >= 0) {
            for (int k = 0; k < n; k++, batchSize++) {
                g[batchSize].i = i;
                g[batchSize].j = second[batchSize] = sortedIndex[slots[k]];
                cutoff[batchSize] = uniform->cutoff;
                slotP[batchSize] = p;
                first[batchSize] = i;
            }
            return n;
        }
        for (int k = 0; k < count; k++) {
            const int j = sortedIndex[q[k]];
            const double imageVx =
                    sortedHeights ? parameters.imageVelocityX(sortedHeights[p] - sortedHeights[q[k]], d[k][1], boxHeight) : 0.0;
            const int t = table.indexOfTypes(sortedTypes[p], sortedTypes[q[k]]);
            if (parameters.pairGeometry(i, j, t, d[k], g[batchSize], imageVx)) {
                cutoff[batchSize] = table.cutoff(t);
                slots[batchSize - start] = q[k];
                slotP[batchSize] = p;
                first[batchSize] = i;
                second[batchSize++] = j;
            }
        }
        return batchSize - start;
    }

    void finishBatch(int n, const int* slots, Vec3* forces) {
        if (terms & RandomTerm)  // the same numbers as random.gaussian(), drawn for the whole batch at once
            PairRandomBatch::normals(random, PairRandom::RandomForce, step, first, second, n, xi);
        if ((terms & RandomTerm) && transverse)
            PairRandomBatch::normalVectors(random, PairRandom::TransverseNoise, step, first, second, n, zeta);
        Vec3* dissipative = forces + (separate ? PairSearch::MAX_BLOCK : 0);
        if (fused != nullptr && !(uniform != nullptr && uniform->soft))  // else the rows made them
            fusedForcesAlongE(n, slots);
        DPDThermostatForces::KeptPair* kept = (keep != nullptr ? keptSpace(n) : nullptr);
        int k = 0;
        if (terms == (DissipativeTerm | RandomTerm) && !transverse) {
            const DPDBatchPairs pairs{g, slotP, slots, xi, fused != nullptr ? fusedOnPair : nullptr, sortedHeights != nullptr, kept};
            k = dpdPairForceRows(pairs, n, sortedVelocities.data(), invSqrtDt, forces, separate ? dissipative : nullptr);
        }
        if (kept != nullptr)
            keepPairs(k, n, slots, kept);
        for (; k < n; k++) {
            forces[k] = (terms & RandomTerm ? randomForce(k) : Vec3());
            Vec3 fd;
            if (terms & DissipativeTerm)
                fd = DPDPairForce::dissipative(g[k], g[k].relativeVelocity(sortedVelocities[slotP[k]], sortedVelocities[slots[k]]));
            dissipative[k] = (separate ? fd : fd + forces[k]);
            if (fused != nullptr)
                forces[k] += g[k].e * fusedOnPair[k];
        }
        batchSize = 0;
    }

    /** FR of pair k of the batch, across e too where it has transverse friction. */
    Vec3 randomForce(int k) const {
        const Vec3 along = DPDPairForce::random(g[k], xi[k], invSqrtDt);
        return g[k].hasTransverse() ? along + DPDPairForce::transverseRandom(g[k], zeta + 3 * k, invSqrtDt) : along;
    }

    /** fusedOnPair[0, n) from the fused force, given each pair's type pair in its table and distance. */
    void fusedForcesAlongE(int n, const int* slots) {
        const TypePairTable& table = fused->getTable();
        for (int k = 0; k < n; k++) {
            fusedTypes[k] = table.indexOfTypes(sortedFusedTypes[slotP[k]], sortedFusedTypes[slots[k]]);
            distance[k] = cutoff[k] * (1 - g[k].wR);
        }
        if (sortedFusedValues != nullptr)
            for (int k = 0; k < n; k++)
                valueSums[k] = sortedFusedValues[slotP[k]] + sortedFusedValues[slots[k]];
        fused->pairForces(n, first, second, fusedTypes, distance, valueSums, fusedOnPair);
    }

    /** Pairs [from, n) of the batch to kept[from, n) (the rows copy those before), and every pair's image velocity. */
    void keepPairs(int from, int n, const int* slots, DPDThermostatForces::KeptPair* kept) {
        for (int k = from; k < n; k++) {
            kept[k].p = slotP[k];
            kept[k].q = slots[k];
            kept[k].e = g[k].e;
            kept[k].gammaWD = g[k].gammaWD;
        }
        if (keepImageVx != nullptr)
            for (int k = 0; k < n; k++)
                (*keepImageVx)[keptCount + k] = g[k].imageVx;
        if (keepTransverse != nullptr)
            for (int k = 0; k < n; k++)
                (*keepTransverse)[keptCount + k] = g[k].transverseGammaWD;
        keptCount += n;
    }

    /**
     * Room for n more kept pairs (and image velocities), where they are written field by
     * field: a pushed temporary is stored and reloaded in pieces that the processor cannot
     * forward, a stall per pair.  The vectors keep their length from step to step (grown,
     * never cleared), so that they are not zeroed again as they grow.
     */
    DPDThermostatForces::KeptPair* keptSpace(int n) {
        if (keptCount + n > keep->size())
            keep->resize(keptCount + n);
        if (keepImageVx != nullptr && keptCount + n > keepImageVx->size())
            keepImageVx->resize(keptCount + n);
        if (keepTransverse != nullptr && keptCount + n > keepTransverse->size())
            keepTransverse->resize(keptCount + n);
        return keep->data() + keptCount;
    }
};

} // namespace

void DPDThermostatForces::sumPairForcesBySlot(int w, int terms, bool separate, const FusedPairForce* fused, long long step,
                                              double dt, bool keep) {
    // Kept in a vector of this worker's own, as in findWorkerPairs.
    std::vector<KeptPair> kept;
    std::vector<double> keptVx, keptTransverse;
    kept.swap(keptPairs[w]);
    keptVx.swap(keptImageVx[w]);
    keptTransverse.swap(keptTransverseGammaWD[w]);
    const bool sheared = !sortedHeights.empty(), transverse = parameters.hasTransverse();
    std::unique_ptr<DPDSlotForces> evaluate(
            new DPDSlotForces{parameters, random, search.getSortedIndex(), *slotVelocities, sortedTypes, sortedFusedTypes,
                              fused != nullptr && fused->getParticleValues() != nullptr ? sortedFusedValues.data() : nullptr,
                              sheared ? sortedHeights.data() : nullptr, searchedHeight, fused, keep ? &kept : nullptr,
                              keep && sheared ? &keptVx : nullptr, keep && transverse ? &keptTransverse : nullptr, terms, separate,
                              step, 1 / std::sqrt(dt), transverse});
    UniformPairRule rule;
    if (canRunUniformPairBlock() && ((fused != nullptr && uniformRule(fused, rule)) || uniformRule(nullptr, rule)))
        evaluate->uniform = &rule;
    std::vector<Vec3>* out[2] = {&workerDissipative[w], separate ? &workerRandom[w] : nullptr};
    accumulateBySlot(search, w, executor.getNumWorkers(), *evaluate, out, separate ? 2 : 1);
    kept.swap(keptPairs[w]);
    keptVx.swap(keptImageVx[w]);
    keptTransverse.swap(keptTransverseGammaWD[w]);
    keptPairCount[w] = evaluate->keptCount;
}

namespace {

/** FD of one kept pair, its j image moving with imageVx, with transverse friction transverseGammaWD. */
Vec3 keptDissipative(const DPDThermostatForces::KeptPair& pair, double imageVx, double transverseGammaWD, const Vec3* v) {
    PairGeometry g;
    g.e = pair.e;
    g.gammaWD = pair.gammaWD;
    g.imageVx = imageVx;
    g.transverseGammaWD = transverseGammaWD;
    return DPDPairForce::dissipative(g, g.relativeVelocity(v[pair.p], v[pair.q]));
}

} // namespace

void DPDThermostatForces::sumKeptDissipative(int w) {
    std::vector<Vec3>& out = workerDissipative[w];
    workerReach[w].zero(out);
    const KeptPair* kept = keptPairs[w].data();
    const double* imageVx = (sortedHeights.empty() ? nullptr : keptImageVx[w].data());  // sheared as in the pass that kept them
    const double* transverse = (parameters.hasTransverse() ? keptTransverseGammaWD[w].data() : nullptr);
    const Vec3* v = slotVelocities->data();
    const size_t count = keptPairCount[w];
    // The forces a chunk at a time (four pairs at a time where the rows run); the pairs come
    // in runs of one slot p (as they were found), whose forces on p are summed in a
    // register, which keeps the loop free of a store-load chain through out[p].
    const int chunk = 64;
    Vec3 f[chunk], forceP;
    int p = (count > 0 ? kept[0].p : 0);
    for (size_t start = 0; start < count; start += chunk) {
        const int n = (int) std::min<size_t>(chunk, count - start);
        const double* chunkImageVx = (imageVx != nullptr ? imageVx + start : nullptr);
        // (The rows have no transverse friction.)
        for (int k = (transverse ? 0 : dpdKeptDissipativeRows(kept + start, chunkImageVx, n, v, f)); k < n; k++)
            f[k] = keptDissipative(kept[start + k], chunkImageVx != nullptr ? chunkImageVx[k] : 0.0,
                                   transverse != nullptr ? transverse[start + k] : 0.0, v);
        for (int k = 0; k < n; k++) {
            const KeptPair& pair = kept[start + k];
            if (pair.p != p) {
                out[p] += forceP;
                forceP = Vec3();
                p = pair.p;
            }
            forceP += f[k];
            out[pair.q] -= f[k];
        }
    }
    if (count > 0)
        out[p] += forceP;
}

void DPDThermostatForces::drawNormals(PairRandom::Stream stream, long long step, std::vector<double>& xi) {
    xi.resize(getNumPairs());
    forEachChunkOfPairs([&](size_t start, int n, const int* first, const int* second) {
        PairRandomBatch::normals(random, stream, step, first, second, n, &xi[start]);
    });
}

void DPDThermostatForces::drawNormalVectors(PairRandom::Stream stream, long long step, std::vector<double>& zeta) {
    zeta.resize(3 * getNumPairs());
    forEachChunkOfPairs([&](size_t start, int n, const int* first, const int* second) {
        PairRandomBatch::normalVectors(random, stream, step, first, second, n, &zeta[3 * start]);
    });
}

void DPDThermostatForces::drawNormalsAndPartners(PairRandom::Stream stream, long long step, std::vector<double>& xi,
                                                std::vector<double>& partners) {
    xi.resize(getNumPairs());
    partners.resize(getNumPairs());
    forEachChunkOfPairs([&](size_t start, int n, const int* first, const int* second) {
        PairRandomBatch::normalsAndPartners(random, stream, step, first, second, n, &xi[start], &partners[start]);
    });
}

void DPDThermostatForces::drawBits(PairRandom::Stream stream, long long step, std::vector<r123::Philox4x32::ctr_type>& words) {
    words.resize(getNumPairs());
    forEachChunkOfPairs([&](size_t start, int n, const int* first, const int* second) {
        PairRandomBatch::bits(random, stream, step, first, second, n, &words[start]);
    });
}
