#ifndef OPENMMDPD_COMMONPAIRRANDOMCHECK_H_
#define OPENMMDPD_COMMONPAIRRANDOMCHECK_H_

#include "openmmdpd/PairRandom.h"
#include "openmm/common/ComputeContext.h"
#include <cstdint>
#include <vector>

namespace DPDPlugin {

/** A pair's key for drawDevicePairRandom. */
struct PairRandomKey {
    PairRandom::Stream stream;
    long long step;
    int i, j;
};

/**
 * For the tests: the device's Philox words (four per key) and Box-Muller normals
 * (kernels/philox.cc), to hold against PairRandom on the host.
 */
void drawDevicePairRandom(OpenMM::ComputeContext& cc, uint32_t seed, const std::vector<PairRandomKey>& keys,
                          std::vector<uint32_t>& words, std::vector<float>& normals);

} // namespace DPDPlugin

#endif
