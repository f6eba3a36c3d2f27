#ifndef OPENMMDPD_PAIRRANDOM_H_
#define OPENMMDPD_PAIRRANDOM_H_

#include "openmm/internal/OSRngSeed.h"
#include <Random123/philox.h>
#include <cmath>
#include <cstdint>

namespace DPDPlugin {

/**
 * Per-pair random numbers from a counter-based generator (Philox4x32-10, Random123).
 *
 * A draw is a pure function of (seed, stream, step, min(i,j), max(i,j)): it is symmetric
 * in i and j, does not depend on the order in which pairs are visited or on the number of
 * threads, and is the same on every platform.  `stream` separates independent uses within
 * one step (e.g. the random force and a Lowe-Andersen acceptance test).  This is the
 * definition; a platform may draw the same words faster (the CPU's PairRandomBatch).
 */
class PairRandom {
public:
    enum Stream : uint32_t {
        RandomForce = 0, PairThermalisation = 1,
        // (2 was S2's second sweep, which now takes partnerGaussian of the next step's RandomForce)
        AuxiliaryNoise = 3,    // EDPD: the noise of a pair variable's step
        AuxiliaryRecall = 4,   // EDPD: a pair variable drawn or caught up when a pair (re)appears
        TransverseNoise = 5,   // transverse friction: the noise across e (a force's, or a sweep's)
        TransverseSecondSweep = 6  // transverse friction: S2's second sweep
    };

    explicit PairRandom(uint32_t seed = 0) : seed(seed) {}
    /** The seed to use for an integrator's seed setting: itself, or a new one for 0. */
    static uint32_t seedFor(int setting) { return setting != 0 ? (uint32_t) setting : (uint32_t) osrngseed(); }
    uint32_t getSeed() const { return seed; }

    /** Four independent 32-bit words for the pair (i, j) at a step. */
    r123::Philox4x32::ctr_type bits(Stream stream, long long step, int i, int j) const {
        if (i > j) {
            int t = i; i = j; j = t;
        }
        const uint64_t s = (uint64_t) step;
        r123::Philox4x32::ctr_type counter = {{(uint32_t) s, (uint32_t) (s >> 32), (uint32_t) i, (uint32_t) j}};
        r123::Philox4x32::key_type key = {{seed, (uint32_t) stream}};
        return r123::Philox4x32()(counter, key);
    }

    /** A standard normal number for the pair (Box-Muller on the first two words). */
    double gaussian(Stream stream, long long step, int i, int j) const {
        return boxMuller(bits(stream, step, i, j));
    }

    /**
     * The other standard normal number of the same Box-Muller pair (the sine where gaussian()
     * takes the cosine): independent of gaussian() for the same key, so a step that needs
     * two numbers for a pair that the next step keys again (S2's second sweep and the next
     * step's first) can draw once for both.
     */
    double partnerGaussian(Stream stream, long long step, int i, int j) const {
        return boxMullerPartner(bits(stream, step, i, j));
    }

    /**
     * The noise vector of transverse friction on i, out[0..2], of which the pair rules take the
     * part perpendicular to e: three independent standard normal numbers (both of Box-Muller
     * on the first two words, the first on the last two) for the lower index, their negatives
     * for the higher, so that i and j get opposite forces whichever is named first.
     */
    void normalVector(Stream stream, long long step, int i, int j, double* out) const {
        const r123::Philox4x32::ctr_type r = bits(stream, step, i, j);
        const double sign = (i < j ? 1.0 : -1.0);
        out[0] = sign * boxMuller(r);
        out[1] = sign * boxMullerPartner(r);
        out[2] = sign * boxMuller(r[2], r[3]);
    }

    /** A uniform number in [0, 1) from one word of a draw. */
    static double toUniform(uint32_t x) {
        return (double) x * (1.0 / 4294967296.0);
    }

    /** A uniform number in (0, 1] from one word: its logarithm is finite. */
    static double toOpenUniform(uint32_t x) {
        return ((double) x + 1.0) * (1.0 / 4294967296.0);
    }

    /** A standard normal number from the first two words of a draw (textbook Box-Muller). */
    static double boxMuller(const r123::Philox4x32::ctr_type& r) { return boxMuller(r[0], r[1]); }
    /** The same from two words. */
    static double boxMuller(uint32_t first, uint32_t second) {
        return boxMullerRadius(first) * std::cos(boxMullerAngle(second));
    }

    /** The partner of boxMuller(): the sine of the same angle. */
    static double boxMullerPartner(const r123::Philox4x32::ctr_type& r) {
        return boxMullerRadius(r[0]) * std::sin(boxMullerAngle(r[1]));
    }

private:
    /** Box-Muller's radius sqrt(-2 log u) and angle 2 pi u', the same for both numbers of the pair. */
    static double boxMullerRadius(uint32_t first) { return std::sqrt(-2.0 * std::log(toOpenUniform(first))); }
    static double boxMullerAngle(uint32_t second) { return 2.0 * M_PI * toUniform(second); }

    uint32_t seed;
};

} // namespace DPDPlugin

#endif
