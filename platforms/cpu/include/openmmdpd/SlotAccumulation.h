#ifndef OPENMMDPD_SLOTACCUMULATION_H_
#define OPENMMDPD_SLOTACCUMULATION_H_

#include "openmmdpd/PairSearch.h"
#include <algorithm>
#include <vector>

namespace DPDPlugin {

/**
 * The CPU platform's accumulate loop for pair forces found on the fly: worker w visits the
 * pair blocks of its cells (PairSearch::workerCells) and adds each accepted pair's force f
 * to slot p and -f to slot q of its own buffer, by cell-sorted slot (neighbouring pairs
 * touch neighbouring memory); the caller adds the buffers in worker order, so the result
 * does not depend on scheduling.
 *
 * The evaluator sees a block of candidate pairs of slot p, keeps those within range and
 * writes their forces on p:  int operator()(int p, const int* q, const OpenMM::Vec3* d,
 * int count, int* acceptedSlots, OpenMM::Vec3* forces)  returns how many it kept.  With
 * `outputs` buffers it writes output t of accepted pair k to forces[t * MAX_BLOCK + k].
 */
template <class Evaluator>
void accumulateBySlot(const PairSearch& search, int w, int workers, Evaluator& evaluate, std::vector<OpenMM::Vec3>* const* slotForce,
                      int outputs = 1) {
    for (int t = 0; t < outputs; t++)
        std::fill(slotForce[t]->begin(), slotForce[t]->begin() + search.getSortedIndex().size(), OpenMM::Vec3());
    size_t begin, end;
    search.workerCells(w, workers, begin, end);
    int slots[PairSearch::MAX_BLOCK];
    std::vector<OpenMM::Vec3> forces(outputs * PairSearch::MAX_BLOCK);
    search.forEachSortedPairBlock((int) begin, (int) end, [&](int p, const int* q, const OpenMM::Vec3* d, int count) {
        const int n = evaluate(p, q, d, count, slots, forces.data());
        for (int t = 0; t < outputs; t++) {
            std::vector<OpenMM::Vec3>& out = *slotForce[t];
            const OpenMM::Vec3* f = forces.data() + t * PairSearch::MAX_BLOCK;
            OpenMM::Vec3 forceP;  // summed here, not in out[p], to keep the loop free of a store-load chain
            for (int k = 0; k < n; k++) {
                forceP += f[k];
                out[slots[k]] -= f[k];
            }
            out[p] += forceP;
        }
    });
}

template <class Evaluator>
void accumulateBySlot(const PairSearch& search, int w, int workers, Evaluator& evaluate, std::vector<OpenMM::Vec3>& slotForce) {
    std::vector<OpenMM::Vec3>* out = &slotForce;
    accumulateBySlot(search, w, workers, evaluate, &out, 1);
}

} // namespace DPDPlugin

#endif
