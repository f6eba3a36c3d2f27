#ifndef OPENMMDPD_DPDTHERMOSTATFORCES_H_
#define OPENMMDPD_DPDTHERMOSTATFORCES_H_

#include "openmmdpd/DPDPairCore.h"
#include "openmmdpd/ParallelExecutor.h"
#include "openmmdpd/UniformPairBlock.h"
#include <algorithm>
#include <array>
#include <string>
#include <vector>

namespace DPDPlugin {

/**
 * The thermostat half of every pair-force DPD step: the pair list at the current
 * positions and the dissipative/random per-particle forces from it, computed over a
 * ParallelExecutor.  Integrators with a pair-force update rule (DPD-VV family, the
 * staggered scheme) call this; pairwise-sequential rules use the same pair list.
 */
class FusedPairForce;
class SoftRepulsionKernel;

class DPDThermostatForces {
public:
    /**
     * @param cellMultiple  see PairSearch (3 for integrators that sweep pairs sequentially)
     */
    DPDThermostatForces(const OpenMM::System& system, const DPDThermostatIntegrator& integrator, ParallelExecutor& executor,
                        int cellMultiple = 1);
    const DPDPairParameters& getParameters() const { return parameters; }
    /** New thermostat parameters (a live change): the pairs are found anew from the next search. */
    void setParameters(const OpenMM::System& system, const DPDThermostatIntegrator& integrator);
    /**
     * Find the pairs within their cutoffs at these positions; given fused (whose pairs must
     * all lie within the thermostat's), fusedOut = its forces, summed in the same pass.
     * bySlot: the pairs' i and j are their cell-sorted slots (see arePairsBySlot), and
     * each worker's part of the list stays where the worker wrote it (see getCellPairs).
     */
    void updatePairs(const std::vector<OpenMM::Vec3>& positions, const OpenMM::Vec3* box,
                     const FusedPairForce* fused = nullptr, std::vector<OpenMM::Vec3>* fusedOut = nullptr,
                     bool bySlot = false);
    /** The pair list, in one piece: after updatePairs by particle (by slot it may be in parts, or of UniformPair: see getCellPairs, getCellUniformPairs). */
    const std::vector<PairGeometry>& getPairs() const;
    /** The number of pairs in the list: the pairs (and their random numbers) are numbered [0, getNumPairs()). */
    size_t getNumPairs() const { return cellPairStart.empty() ? 0 : (size_t) cellPairStart.back(); }
    /**
     * Whether the pairs' i and j name cell-sorted slots (particle getSearch().getSortedIndex()[i])
     * instead of particles: a sweep over velocities in slot order touches neighbouring
     * memory, where by particle index it would hit memory at random in a large system.
     * Only drawNormals() and the sweeps take such a list.
     */
    bool arePairsBySlot() const { return pairsBySlot; }
    /** The pairs found from cell c are numbered [getCellPairStart()[c], getCellPairStart()[c + 1]). */
    const std::vector<int>& getCellPairStart() const { return cellPairStart; }
    /**
     * Where the geometry of cell c's first pair lies, the others following it: by slot, the
     * workers' parts of the list are not copied into one (a copy at memory speed that adds no
     * pair; README, "At scale").  Valid until the next updatePairs, which alone resizes the
     * lists they point into; stale where arePairsUniform().
     */
    const std::vector<const PairGeometry*>& getCellPairs() const { return cellPairs; }
    /**
     * Whether the list by slot is one of UniformPair, each pair's geometry given by
     * getUniformRule() and the entry (where every pair shares its parameters, and the
     * processor runs uniformPairBlock): then getCellUniformPairs() says where each cell's
     * pairs lie, and getCellPairs() is stale.
     */
    bool arePairsUniform() const { return pairsUniform; }
    const UniformPairRule& getUniformRule() const { return listRule; }
    const std::vector<const UniformPair*>& getCellUniformPairs() const { return cellUniformPairs; }
    const PairSearch& getSearch() const { return search; }
    const PairRandom& getRandom() const { return random; }
    /**
     * Overwrite dissipative and/or random (per `terms`) with the pair forces; given the
     * same array for both, it receives their sum.
     */
    void compute(int terms, const std::vector<OpenMM::Vec3>& velocities, long long step, double dt,
                 std::vector<OpenMM::Vec3>& dissipative, std::vector<OpenMM::Vec3>& random);
    /**
     * virial += the virial sum r_ij F_ij of the pair forces compute() gives for these terms
     * (both: FD + FR), over the current pair list; reads the velocities only.
     */
    void addVirial(int terms, const std::vector<OpenMM::Vec3>& velocities, long long step, double dt, SymmetricTensor& virial);
    /**
     * out[i] = sum over the pairs of c_k e_k, with + on the pair's particle i and - on j:
     * the per-particle force of pair forces c_k e_k given per pair (in getPairs() order).
     */
    void sumAlongPairs(const std::vector<double>& c, std::vector<OpenMM::Vec3>& out);
    /**
     * out = base + FD(velocities) + FR at these positions, plus fused's pair forces when fused
     * is given (its pairs must all lie within the thermostat's; base may be null): the same
     * pairs and numbers as updatePairs() and compute(), for update rules that use every
     * pair once per evaluation: searchSlots() and one sumBySlot().
     */
    void computeInOnePass(const std::vector<OpenMM::Vec3>& positions, const OpenMM::Vec3* box,
                          const std::vector<OpenMM::Vec3>& velocities, long long step, double dt,
                          const FusedPairForce* fused, const std::vector<OpenMM::Vec3>* base,
                          std::vector<OpenMM::Vec3>& out);
    /**
     * Where a slot pass gets its pairs: found in the cells (FindPairs), found and kept by
     * each worker (FindAndKeepPairs), or those kept by the last FindAndKeepPairs pass since
     * searchSlots() (KeptPairs: FD only, no fused force, no base), read back in order
     * (cheaper than finding them again, when the same pairs need FD at new velocities).
     */
    enum PairSource { FindPairs, FindAndKeepPairs, KeptPairs };
    /**
     * Sort the particles into cells at these positions (which must stay alive and unchanged
     * until the last sumBySlot() that follows) for passes over the pairs with sumBySlot().
     * getPairs() is left stale.
     */
    void searchSlots(const std::vector<OpenMM::Vec3>& positions, const OpenMM::Vec3* box);
    /**
     * How sumBySlot's velocities or outputs are indexed: by particle, or by slot of the last
     * searchSlots() (particle getSearch().getSortedIndex()[k] at k; only as many entries),
     * for an update rule that keeps its particles in slot order between passes instead of
     * going through memory at random to particle order and back.
     */
    enum Indexing { ByParticle, BySlot };
    /**
     * out = base + the forces of `terms` at these velocities + fused's pair forces (if fused is
     * given; see computeInOnePass), or with dissipativeOut FD there and the rest in out (base,
     * by particle, may be null): the pairs of the last searchSlots() found and used in one
     * pass over the cell-sorted slots, so no pair list is written and read back.
     */
    void sumBySlot(int terms, const std::vector<OpenMM::Vec3>& velocities, long long step, double dt,
                   const FusedPairForce* fused, const std::vector<OpenMM::Vec3>* base, std::vector<OpenMM::Vec3>& out,
                   std::vector<OpenMM::Vec3>* dissipativeOut = nullptr, PairSource source = FindPairs,
                   Indexing velocityIndexing = ByParticle, Indexing outputIndexing = ByParticle);
    /** The velocities the last sumBySlot() used, by slot. */
    const std::vector<OpenMM::Vec3>& getSlotVelocities() const { return *slotVelocities; }
    /**
     * A pair that a FindAndKeepPairs pass accepted: what FD needs of it, by slot (40 bytes,
     * written and read back once a step for every pair; its image velocity, under shear only,
     * beside it in a list of its own).
     */
    struct KeptPair {
        int p, q;
        OpenMM::Vec3 e;
        double gammaWD;
    };
    /** zeta[3k, 3k + 3) = getRandom().normalVector(stream, step, pair k), for every pair of the list, in batches. */
    void drawNormalVectors(PairRandom::Stream stream, long long step, std::vector<double>& zeta);
    /** xi[k] = getRandom().gaussian(stream, step, pair k), for every pair of the list, in batches. */
    void drawNormals(PairRandom::Stream stream, long long step, std::vector<double>& xi);
    /** drawNormals, and partners[k] = getRandom().partnerGaussian(stream, step, pair k) from the same draws. */
    void drawNormalsAndPartners(PairRandom::Stream stream, long long step, std::vector<double>& xi, std::vector<double>& partners);
    /** words[k] = getRandom().bits(stream, step, pair k), for every pair of the list, in batches. */
    void drawBits(PairRandom::Stream stream, long long step, std::vector<r123::Philox4x32::ctr_type>& words);
    void setSeed(uint32_t seed) { random = PairRandom(seed); }
    uint32_t getSeed() const { return random.getSeed(); }


private:
    struct PairParticles {
        int i, j;
    };
    /** use(start, n, i, j): the particles of the pairs [start, start + n), a chunk of a worker's part at a time, in parallel. */
    template <class Use>
    void forEachChunkOfPairs(Use use) const {
        constexpr size_t CHUNK = 64;
        const int parts = (pairsInParts ? executor.getNumWorkers() : 1);
        std::vector<size_t> chunksBefore(parts + 1, 0);
        for (int v = 0; v < parts; v++)
            chunksBefore[v + 1] = chunksBefore[v] + (partSize(v) + CHUNK - 1) / CHUNK;
        executor.execute([&](int w) {
            size_t begin, end;
            executor.range(w, chunksBefore.back(), begin, end);
            int first[CHUNK], second[CHUNK];
            for (size_t c = begin; c < end; c++) {
                const int v = (int) (std::upper_bound(chunksBefore.begin(), chunksBefore.end(), c) - chunksBefore.begin()) - 1;
                const size_t local = (c - chunksBefore[v]) * CHUNK, n = std::min(CHUNK, partSize(v) - local);
                const PairParticles* particles = (v == 0 ? pairParticles : workerPairParticles[v]).data() + local;
                for (size_t k = 0; k < n; k++) {
                    first[k] = particles[k].i;
                    second[k] = particles[k].j;
                }
                use(workerPairsBefore(v) + local, (int) n, first, second);
            }
        });
    }
    /** The number of pairs in part v of the list (pairsInParts), or in the whole list (v = 0). */
    size_t partSize(int v) const { return pairsInParts ? workerListSize[v] : getNumPairs(); }
    /** The pair search needs the cutoff to fit in half the periodic box. */
    void checkCutoffFitsBox(const OpenMM::Vec3* box) const;
    /** out[i] = the sum of the workers' buffers at i, in worker order, for worker w's range of i. */
    void reduceWorkerBuffers(int w, const std::vector<std::vector<OpenMM::Vec3>>& buffers, std::vector<OpenMM::Vec3>& out) const;
    /** The pair-list accumulate loop (accumulateAlongPairs) on every worker, buffers reduced in worker order. */
    template <class Evaluator>
    void sumOverPairs(const Evaluator& evaluator, std::array<std::vector<OpenMM::Vec3>*, Evaluator::OUTPUTS> out);
    /** The sum of the buffers at index k, in worker order (inline: it runs once per particle, in loops over them). */
    static OpenMM::Vec3 sumOverWorkers(const std::vector<std::vector<OpenMM::Vec3>>& buffers, size_t k) {
        OpenMM::Vec3 f;
        for (const std::vector<OpenMM::Vec3>& buffer : buffers)
            f += buffer[k];
        return f;
    }
    /**
     * updatePairs' steps: worker w's pairs (and their particles), worker 0's into the list
     * itself; by particle, the list sized for all workers', and w's share of the other
     * workers' parts copied in.
     */
    void findWorkerPairs(int w, const FusedPairForce* fused);
    /**
     * findWorkerPairs' frame for a list of either entry: worker w's part of it (and of the
     * pairs' particles) grown in place by appendBlock(p, qs, ds, hits, out, outParticles,
     * count, fusedForce) for each block of hits of its cells.
     */
    template <class Entry, class AppendBlock>
    void fillWorkerList(int w, const FusedPairForce* fused, std::vector<Entry>& firstPart, std::vector<std::vector<Entry>>& otherParts,
                        AppendBlock appendBlock);
    /** findWorkerPairs for one block of hits, pair by pair (what uniformPairBlock does four at a time);
     *  soft is the fused force where it is the soft repulsion, made inline. */
    void appendPairsOneByOne(int p, const int* qs, const OpenMM::Vec3* ds, int hits, std::vector<PairGeometry>& out,
                             std::vector<PairParticles>& outParticles, size_t& count, std::vector<OpenMM::Vec3>& fusedForce,
                             const FusedPairForce* fused, const SoftRepulsionKernel* soft) const;
    /** Whether every pair shares its parameters (UniformPairRule), and if so, those. */
    bool uniformRule(const FusedPairForce* fused, UniformPairRule& rule) const;
    /**
     * findWorkerPairs for one block of p's hits through uniformPairBlock, appended at count,
     * and the forces of `fused` (where given: one the rule does not make) added to fusedForce;
     * false where that cannot run.
     */
    template <class Entry>
    bool appendUniformPairs(const UniformPairRule& rule, int p, const int* qs, const OpenMM::Vec3* ds, int hits,
                            std::vector<Entry>& out, std::vector<PairParticles>& outParticles, size_t& count,
                            std::vector<OpenMM::Vec3>& fusedForce, const FusedPairForce* fused) const;
    /**
     * The forces of `fused` on the n accepted pairs (p, acceptedQ[k]) of one block, at
     * distances r[k] along accepted[k].e, added to fusedForce by slot pair by pair in order:
     * one call into the force per block, not per pair.
     */
    template <class Entry>
    void addFusedForces(const FusedPairForce& fused, int p, const int* acceptedQ, const Entry* accepted, const double* r, int n,
                        std::vector<OpenMM::Vec3>& fusedForce) const;
    size_t workerPairsBefore(int w) const;
    /** Worker w's cells: where their pairs lie (cellPairs), and their offsets into its own list made numbers in the whole list. */
    void placeWorkerCells(int w);
    /** placeWorkerCells' pointers, into a list of either entry. */
    template <class Entry>
    void pointCellsInto(int w, size_t begin, size_t end, size_t offset, const std::vector<Entry>& firstPart,
                        const std::vector<std::vector<Entry>>& otherParts, std::vector<const Entry*>& cellEntries);
    template <class Entry>
    void sizeForWorkerLists(std::vector<Entry>& list) const;
    template <class Entry>
    void copyWorkerLists(int w, const std::vector<std::vector<Entry>>& workerLists, std::vector<Entry>& list) const;
    /** sortedTypes (and sortedHeights if asked), or sortedFusedTypes (and sortedFusedValues), for the slots [begin, end) of the last search. */
    void sortTypes(size_t begin, size_t end, bool heights);
    void sortFusedTypes(size_t begin, size_t end, const FusedPairForce& fused);
    /** sumBySlot's pair pass: worker w's cells' pair forces into its buffers (FD into the second if separate), by slot. */
    void sumPairForcesBySlot(int w, int terms, bool separate, const FusedPairForce* fused, long long step, double dt,
                             bool keep);
    /** The KeptPairs pass: FD of worker w's kept pairs into its buffer, by slot. */
    void sumKeptDissipative(int w);
    std::string name;  // the integrator's class, for error messages
    DPDPairParameters parameters;
    ParallelExecutor& executor;
    PairSearch search;
    int cellMultiple;
    PairRandom random;
    std::vector<PairGeometry> pairs;
    bool pairsBySlot = false;
    bool pairsInParts = false;  // by slot with several workers: worker w's part of the list in its own vectors
    std::vector<int> cellPairStart;
    std::vector<const PairGeometry*> cellPairs;
    std::vector<std::vector<PairGeometry>> workerPairs;  // workers 1, 2, ...: their parts of the list
    // The list by slot where pairsUniform, as `pairs`, `cellPairs` and `workerPairs` otherwise
    bool pairsUniform = false;
    UniformPairRule listRule{};
    std::vector<UniformPair> uniformPairs;
    std::vector<const UniformPair*> cellUniformPairs;
    std::vector<std::vector<UniformPair>> workerUniformPairs;
    std::vector<size_t> workerListSize;                 // each worker's number of pairs
    // Each pair's particles, by list index: what drawing its numbers reads (8 bytes, where
    // reading them from the list would bring its 40 or 72 bytes in from memory once more).
    std::vector<PairParticles> pairParticles;
    std::vector<std::vector<PairParticles>> workerPairParticles;
    std::vector<std::vector<OpenMM::Vec3>> workerDissipative, workerRandom;
    std::vector<PairSearch::SlotReach> workerReach;  // of each worker's buffers by slot, for the last search
    std::vector<OpenMM::Vec3> sortedVelocities;             // the velocities by particle, copied into slot order
    const std::vector<OpenMM::Vec3>* slotVelocities = nullptr;  // sortedVelocities, or those given by slot
    std::vector<double> sortedHeights;  // y of each slot's particle as stored (under shear only)
    // Each slot's particle's type in the thermostat's table and in the fused force's: read
    // per pair, where a lookup by particle index would hit memory at random.
    std::vector<int> sortedTypes, sortedFusedTypes;
    std::vector<double> sortedFusedValues;  // the fused force's particle values by slot, where it has them
    std::vector<std::vector<KeptPair>> keptPairs;  // each worker's, by its FindAndKeepPairs pass
    std::vector<std::vector<double>> keptImageVx;  // and their image velocities (read under shear only)
    std::vector<std::vector<double>> keptTransverseGammaWD;  // and their transverse gamma wD (with transverse friction only)
    std::vector<size_t> keptPairCount;             // how many of each worker's are kept (the vectors may be longer)
    // Whether the sorted types (and heights) are those of the last search, and the fused
    // force's too (of sortedFused).
    bool slotsSorted = false, fusedSorted = false;
    const FusedPairForce* sortedFused = nullptr;
    const std::vector<OpenMM::Vec3>* searched = nullptr;  // the positions and box height of the last search
    double searchedHeight = 0;
};

} // namespace DPDPlugin

#endif
