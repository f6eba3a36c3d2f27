#ifndef OPENMMDPD_SLOTACCUMULATION_H_
#define OPENMMDPD_SLOTACCUMULATION_H_

#include "openmmdpd/PairSearch.h"
#include <algorithm>
#include <vector>

namespace DPDPlugin {

/**
 * accumulateBySlot's adding of a batch: for each block b, -f to the other slot of each of its
 * pairs and the block's sum to its slot p, in every output buffer.  The outputs share one
 * loop over the pairs (each buffer's sums in the same order as alone).
 */
template <int Outputs>
void addBatchBySlot(std::vector<OpenMM::Vec3>* const* slotForce, const OpenMM::Vec3* forces, const int* slots, const int* blockSlot,
                    const int* blockEnd, int blocks) {
    OpenMM::Vec3* out[Outputs];
    for (int t = 0; t < Outputs; t++)
        out[t] = slotForce[t]->data();
    for (int b = 0, k = 0; b < blocks; b++) {
        OpenMM::Vec3 forceP[Outputs];  // summed here, not in out[p], to keep the loop free of a store-load chain
        for (; k < blockEnd[b]; k++)
            for (int t = 0; t < Outputs; t++) {
                const OpenMM::Vec3& f = forces[t * PairSearch::MAX_BLOCK + k];
                forceP[t] += f;
                out[t][slots[k]] -= f;
            }
        for (int t = 0; t < Outputs; t++)
            out[t][blockSlot[b]] += forceP[t];
    }
}

/**
 * The CPU platform's accumulate loop for pair forces found on the fly: worker w visits the
 * pair blocks of its cells (PairSearch::workerCells) and adds each accepted pair's force f
 * to slot p and -f to slot q of its own buffer, by cell-sorted slot (neighbouring pairs
 * touch neighbouring memory); the caller adds the buffers in worker order, so the result
 * does not depend on scheduling.  Only the worker's reach (PairSearch::workerSlotReach) of
 * its buffer is zeroed and written.
 *
 * The evaluator sees a block of candidate pairs of slot p, keeps those within range and
 * may write their forces on p at once:  int operator()(int p, const int* q, const
 * OpenMM::Vec3* d, int count, int* acceptedSlots, OpenMM::Vec3* forces)  returns how many
 * it kept.  Blocks are gathered into batches of up to MAX_BLOCK kept pairs, block after
 * block: acceptedSlots and forces point at the block's position in the batch, which is the
 * number of pairs kept since the last finishBatch (so an evaluator may index scratch of its
 * own the same way).  Before a batch is added,  void finishBatch(int n, const int*
 * acceptedSlots, OpenMM::Vec3* forces)  completes the forces of its n pairs, whose other
 * slots are acceptedSlots[0, n) (a thermostat draws their random numbers
 * together there: ~8 pairs per block are too few to keep the generator's vector lanes
 * busy).  With `outputs` (1 or 2) buffers (distinct vectors) output t of batch pair k is
 * forces[t * MAX_BLOCK + k].  The sums are the same whatever the batches: each block's
 * forces on p are summed, then added, in block order.
 */
template <class Evaluator>
void accumulateBySlot(const PairSearch& search, int w, int workers, Evaluator& evaluate, std::vector<OpenMM::Vec3>* const* slotForce,
                      int outputs = 1) {
    const PairSearch::SlotReach reach = search.workerSlotReach(w, workers);
    for (int t = 0; t < outputs; t++)
        reach.zero(*slotForce[t]);
    size_t begin, end;
    search.workerCells(w, workers, begin, end);
    int slots[PairSearch::MAX_BLOCK], blockSlot[PairSearch::MAX_BLOCK], blockEnd[PairSearch::MAX_BLOCK];
    int kept = 0, blocks = 0;
    std::vector<OpenMM::Vec3> forces(outputs * PairSearch::MAX_BLOCK);
    const auto addBatch = [&]() {
        evaluate.finishBatch(kept, slots, forces.data());
        if (outputs == 1)
            addBatchBySlot<1>(slotForce, forces.data(), slots, blockSlot, blockEnd, blocks);
        else
            addBatchBySlot<2>(slotForce, forces.data(), slots, blockSlot, blockEnd, blocks);
        kept = blocks = 0;
    };
    search.forEachSortedPairBlock((int) begin, (int) end, [&](int p, const int* q, const OpenMM::Vec3* d, int count) {
        if (kept + count > PairSearch::MAX_BLOCK)
            addBatch();
        const int n = evaluate(p, q, d, count, slots + kept, forces.data() + kept);
        if (n > 0) {  // so there are never more blocks than pairs
            kept += n;
            blockSlot[blocks] = p;
            blockEnd[blocks++] = kept;
        }
    });
    addBatch();
}

/**
 * The workers' buffers by slot summed at slot k, in worker order, each read only within its
 * reach (where accumulateBySlot zeroed and wrote it): the same bits as summing them all, as
 * a sum from +0 is unchanged by adding the +0 found elsewhere.
 */
template <class T>
inline T sumWithinReach(const std::vector<std::vector<T>>& buffers, const std::vector<PairSearch::SlotReach>& reach, size_t k) {
    T f = T();
    for (size_t v = 0; v < buffers.size(); v++)
        if (reach[v].contains(k))
            f += buffers[v][k];
    return f;
}

/** An evaluator that writes every force as it keeps the pair, with nothing to finish. */
template <class Function>
struct ImmediateForces {
    Function& evaluate;
    int operator()(int p, const int* q, const OpenMM::Vec3* d, int count, int* slots, OpenMM::Vec3* forces) {
        return evaluate(p, q, d, count, slots, forces);
    }
    void finishBatch(int, const int*, OpenMM::Vec3*) {}
};

/** The same for an evaluator that writes every force as it keeps the pair, into one buffer. */
template <class Evaluator>
void accumulateBySlot(const PairSearch& search, int w, int workers, Evaluator& evaluate, std::vector<OpenMM::Vec3>& slotForce) {
    std::vector<OpenMM::Vec3>* out = &slotForce;
    ImmediateForces<Evaluator> immediate{evaluate};
    accumulateBySlot(search, w, workers, immediate, &out, 1);
}

} // namespace DPDPlugin

#endif
