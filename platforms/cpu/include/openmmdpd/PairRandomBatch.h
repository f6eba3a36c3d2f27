#ifndef OPENMMDPD_PAIRRANDOMBATCH_H_
#define OPENMMDPD_PAIRRANDOMBATCH_H_

#include "openmmdpd/PairRandom.h"

namespace DPDPlugin {

/**
 * PairRandom's numbers drawn many at a time, for the CPU platform's pair loops: the same
 * words (bit for bit), and normal numbers (and their partners) equal to PairRandom::boxMuller's
 * (boxMullerPartner's) to rounding.
 */
struct PairRandomBatch {
    /**
     * out[k] = random.bits(stream, step, i[k], j[k]) for k < n, eight or four pairs at a
     * time where the processor has AVX-512 or AVX2.
     */
    static void bits(const PairRandom& random, PairRandom::Stream stream, long long step, const int* i, const int* j, int n,
                     r123::Philox4x32::ctr_type* out);

    /**
     * out[k] = random.gaussian(stream, step, i[k], j[k]) for k < n, to rounding: where the
     * processor has AVX2 and glibc's vector math library is available, the words of a block
     * of draws (bits()'s arithmetic) are kept as doubles, and their Box-Muller numbers made four
     * at a time (log and cos are most of a normal number's cost).  Every number takes the same
     * path whatever its position in the batch.
     */
    static void normals(const PairRandom& random, PairRandom::Stream stream, long long step, const int* i, const int* j, int n,
                        double* out);
    /** normals() and, where partnerOut is given, partnerOut[k] = random.partnerGaussian(...) to rounding, from the same draws. */
    static void normalsAndPartners(const PairRandom& random, PairRandom::Stream stream, long long step, const int* i, const int* j,
                                   int n, double* out, double* partnerOut);
    /**
     * out[3k, 3k + 3) = random.normalVector(stream, step, i[k], j[k]) for k < n, to rounding:
     * the words as bits() draws them, their three Box-Muller numbers four pairs at a time as
     * normals() makes them.
     */
    static void normalVectors(const PairRandom& random, PairRandom::Stream stream, long long step, const int* i, const int* j, int n,
                              double* out);
};

} // namespace DPDPlugin

#endif
