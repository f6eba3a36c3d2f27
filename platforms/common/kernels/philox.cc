/*
 * Philox4x32-10 (Salmon et al. 2011, Random123), written out for the device: the same words
 * as platforms/core/PairRandom.h draws on the host (checked bit for bit by TestGpuPlatform).
 */

typedef struct {
    unsigned int v[4];
} PhiloxWords;

DEVICE PhiloxWords philox4x32(unsigned int c0, unsigned int c1, unsigned int c2, unsigned int c3, unsigned int k0, unsigned int k1) {
    for (int round = 0; round < 10; round++) {
        if (round > 0) {
            k0 += 0x9E3779B9u;
            k1 += 0xBB67AE85u;
        }
        const mm_ulong p0 = ((mm_ulong) 0xD2511F53u)*c0;
        const mm_ulong p1 = ((mm_ulong) 0xCD9E8D57u)*c2;
        const unsigned int n0 = ((unsigned int) (p1>>32))^c1^k0;
        const unsigned int n2 = ((unsigned int) (p0>>32))^c3^k1;
        c1 = (unsigned int) p1;
        c3 = (unsigned int) p0;
        c0 = n0;
        c2 = n2;
    }
    PhiloxWords out;
    out.v[0] = c0;
    out.v[1] = c1;
    out.v[2] = c2;
    out.v[3] = c3;
    return out;
}

/* The words of the pair (i, j) at a step: counter (step low, step high, min, max), key (seed, stream). */
DEVICE PhiloxWords pairWords(unsigned int seed, unsigned int stream, unsigned int stepLow, unsigned int stepHigh, int i, int j) {
    const int lo = (i < j ? i : j), hi = (i < j ? j : i);
    return philox4x32(stepLow, stepHigh, (unsigned int) lo, (unsigned int) hi, seed, stream);
}

/* Box-Muller's radius sqrt(-2 log u0), u0 in (0, 1], from the first word. */
DEVICE mixed boxMullerRadius(PhiloxWords w) {
    const mixed u0 = ((mixed) w.v[0]+(mixed) 1.0f)*(mixed) 2.3283064365386963e-10f;
    return sqrt(-(mixed) 2.0f*log(u0));
}

/* Box-Muller's angle 2 pi u1, u1 in [0, 1), from the second word. */
DEVICE mixed boxMullerAngle(PhiloxWords w) {
    return (mixed) TWO_PI*(((mixed) w.v[1])*(mixed) 2.3283064365386963e-10f);
}

/* Textbook Box-Muller on the first two words: sqrt(-2 log u0) cos(2 pi u1). */
DEVICE mixed boxMuller(PhiloxWords w) {
    return boxMullerRadius(w)*cos(boxMullerAngle(w));
}

/* Its partner: the sine of the same angle (PairRandom::boxMullerPartner). */
DEVICE mixed boxMullerPartner(PhiloxWords w) {
    return boxMullerRadius(w)*sin(boxMullerAngle(w));
}

/*
 * The noise vector on i of the pair (i, j)'s words (PairRandom::normalVector): both of
 * Box-Muller's numbers on the first two words and the first on the last two, negated where
 * i is the higher index.
 */
DEVICE void normalVector(PhiloxWords w, int i, int j, mixed* out) {
    const mixed sign = (i < j ? 1 : -1);
    PhiloxWords last;
    last.v[0] = w.v[2];
    last.v[1] = w.v[3];
    out[0] = sign*boxMuller(w);
    out[1] = sign*boxMullerPartner(w);
    out[2] = sign*boxMuller(last);
}
