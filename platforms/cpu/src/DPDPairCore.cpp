#include "openmmdpd/DPDPairCore.h"
#include "openmmdpd/PairRandomBatch.h"
#include <algorithm>

using namespace DPDPlugin;
using OpenMM::Vec3;

namespace {

template <bool Dissipative, bool Random, bool Sum>
void accumulate(const std::vector<PairGeometry>& pairs, size_t begin, size_t end, const std::vector<Vec3>& velocities,
                const PairRandom& random, long long step, double invSqrtDt, std::vector<Vec3>& dissipative,
                std::vector<Vec3>& randomForce) {
    // The normal numbers are drawn a chunk of pairs at a time (PairRandomBatch's batches).
    constexpr size_t CHUNK = 64;
    r123::Philox4x32::ctr_type bits[CHUNK];
    int first[CHUNK], second[CHUNK];
    double xi[CHUNK];
    for (size_t k = begin; k < end; k++) {
        const size_t inChunk = (k - begin) % CHUNK;
        if (Random && inChunk == 0) {
            const int n = (int) std::min(CHUNK, end - k);
            for (int c = 0; c < n; c++) {
                first[c] = pairs[k + c].i;
                second[c] = pairs[k + c].j;
            }
            PairRandomBatch::bits(random, PairRandom::RandomForce, step, first, second, n, bits);
            PairRandomBatch::boxMuller(&bits[0][0], &bits[0][1], n, 4, xi);
        }
        const PairGeometry& p = pairs[k];
        Vec3 fd, fr;
        if (Dissipative)
            fd = DPDPairForce::dissipative(p, velocities[p.i] - velocities[p.j]);
        if (Random)
            fr = DPDPairForce::random(p, xi[inChunk], invSqrtDt);
        if (Sum) {
            const Vec3 f = fd + fr;
            dissipative[p.i] += f;
            dissipative[p.j] -= f;
            continue;
        }
        if (Dissipative) {
            dissipative[p.i] += fd;
            dissipative[p.j] -= fd;
        }
        if (Random) {
            randomForce[p.i] += fr;
            randomForce[p.j] -= fr;
        }
    }
}

} // namespace

void DPDPlugin::accumulateDPDForces(const std::vector<PairGeometry>& pairs, size_t begin, size_t end, int terms,
                                    const std::vector<Vec3>& velocities, const PairRandom& random, long long step,
                                    double dt, std::vector<Vec3>& dissipative, std::vector<Vec3>& randomForce) {
    const double invSqrtDt = 1 / std::sqrt(dt);
    const bool both = (terms & DissipativeTerm) && (terms & RandomTerm);
    if (both && &dissipative == &randomForce)
        accumulate<true, true, true>(pairs, begin, end, velocities, random, step, invSqrtDt, dissipative, randomForce);
    else if (both)
        accumulate<true, true, false>(pairs, begin, end, velocities, random, step, invSqrtDt, dissipative, randomForce);
    else if (terms & DissipativeTerm)
        accumulate<true, false, false>(pairs, begin, end, velocities, random, step, invSqrtDt, dissipative, randomForce);
    else if (terms & RandomTerm)
        accumulate<false, true, false>(pairs, begin, end, velocities, random, step, invSqrtDt, dissipative, randomForce);
}
