#ifndef OPENMMDPD_DPDPAIRCORE_H_
#define OPENMMDPD_DPDPAIRCORE_H_

#include "openmmdpd/PairEvaluators.h"
#include "openmmdpd/PairRandomBatch.h"
#include "openmmdpd/PairSearch.h"
#include "openmmdpd/PressureTensor.h"
#include <algorithm>
#include <vector>

namespace DPDPlugin {

/** What a pass over the pairs adds to the per-particle forces. */
enum PairTerms { DissipativeTerm = 1, RandomTerm = 2 };

/**
 * The CPU platform's accumulate loop over a stored pair list: for every pair k in
 * [begin, end) the evaluator gives the force on i of each of its OUTPUTS terms, which is
 * added to out[t][i] and subtracted from out[t][j].  An evaluator is
 * { static constexpr int OUTPUTS; void start(size_t begin, size_t end);
 *   void operator()(size_t k, const PairGeometry& pair, OpenMM::Vec3* forces); }.
 */
template <class Evaluator>
void accumulateAlongPairs(const std::vector<PairGeometry>& pairs, size_t begin, size_t end, Evaluator evaluate,
                          std::vector<OpenMM::Vec3>* const* out) {
    evaluate.start(begin, end);
    OpenMM::Vec3 f[Evaluator::OUTPUTS];
    for (size_t k = begin; k < end; k++) {
        const PairGeometry& p = pairs[k];
        evaluate(k, p, f);
        for (int t = 0; t < Evaluator::OUTPUTS; t++) {
            (*out[t])[p.i] += f[t];
            (*out[t])[p.j] -= f[t];
        }
    }
}

/**
 * The same loop for the pressure tensor: virial += sum over pairs k in [begin, end) of
 * r_k f_k e_k e_k^T, f_k the first output of the evaluator (a force along e_k, or across it
 * too with transverse friction: addPairForceVirial).
 */
template <class Evaluator>
void addVirialAlongPairs(const std::vector<PairGeometry>& pairs, size_t begin, size_t end, Evaluator evaluate,
                         const DPDPairParameters& parameters, SymmetricTensor& virial) {
    evaluate.start(begin, end);
    OpenMM::Vec3 f[Evaluator::OUTPUTS];
    // Summed in a local: the workers' tensors share cache lines.
    SymmetricTensor sum = virial;
    for (size_t k = begin; k < end; k++) {
        const PairGeometry& p = pairs[k];
        evaluate(k, p, f);
        addPairForceVirial(sum, p, pairDistance(p, parameters), f[0]);
    }
    virial = sum;
}

/**
 * FD(v) and/or FR of each pair (docs/theory/dpd.md): one output with the terms asked
 * for (summed if both), or two (FD, FR) when Separate.  The normal numbers are drawn a
 * chunk of pairs at a time (PairRandomBatch), keyed by `step` (transverse friction's pair by
 * pair).
 */
template <bool Dissipative, bool Random, bool Separate>
struct DPDListForces {
    static constexpr int OUTPUTS = Separate ? 2 : 1;
    static constexpr size_t CHUNK = 64;
    const std::vector<PairGeometry>& pairs;
    const std::vector<OpenMM::Vec3>& velocities;
    const PairRandom& random;
    long long step;
    double invSqrtDt;
    size_t end = 0, chunkStart = 0;
    double xi[CHUNK];

    void start(size_t begin, size_t rangeEnd) {
        end = rangeEnd;
        chunkStart = begin;
        drawChunk();
    }
    void operator()(size_t k, const PairGeometry& p, OpenMM::Vec3* f) {
        OpenMM::Vec3 fd, fr;
        if (Dissipative)
            fd = DPDPairForce::dissipative(p, p.relativeVelocity(velocities[p.i], velocities[p.j]));
        if (Random) {
            if (k >= chunkStart + CHUNK) {
                chunkStart = k;
                drawChunk();
            }
            fr = DPDPairForce::random(p, xi[k - chunkStart], invSqrtDt);
            if (p.hasTransverse()) {
                double zeta[3];
                random.normalVector(PairRandom::TransverseNoise, step, p.i, p.j, zeta);
                fr += DPDPairForce::transverseRandom(p, zeta, invSqrtDt);
            }
        }
        f[0] = (Separate ? fd : fd + fr);
        if (Separate)
            f[OUTPUTS - 1] = fr;
    }
    void drawChunk() {
        if (!Random || chunkStart >= end)
            return;
        // (Not std::min, which takes CHUNK by reference: C++14 then needs a definition of it
        // outside the class, and an unoptimised build fails to link.)
        const int n = (int) (end - chunkStart < CHUNK ? end - chunkStart : CHUNK);
        int first[CHUNK], second[CHUNK];
        for (int c = 0; c < n; c++) {
            first[c] = pairs[chunkStart + c].i;
            second[c] = pairs[chunkStart + c].j;
        }
        PairRandomBatch::normals(random, PairRandom::RandomForce, step, first, second, n, xi);
    }
};

/** c_k e_k: pair forces given per pair (in pair-list order) along the pair's unit vector. */
struct PairCoefficientForces {
    static constexpr int OUTPUTS = 1;
    const std::vector<double>& c;
    void start(size_t, size_t) {}
    void operator()(size_t k, const PairGeometry& p, OpenMM::Vec3* f) const { f[0] = p.e * c[k]; }
};

} // namespace DPDPlugin

#endif
