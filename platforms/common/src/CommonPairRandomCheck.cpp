#include "openmmdpd/CommonPairRandomCheck.h"
#include "openmmdpd/CommonCellList.h"
#include "CommonDPDKernelSources.h"
#include "openmm/common/ContextSelector.h"

using namespace DPDPlugin;
using namespace OpenMM;

void DPDPlugin::drawDevicePairRandom(ComputeContext& cc, uint32_t seed, const std::vector<PairRandomKey>& keys,
                                     std::vector<uint32_t>& words, std::vector<float>& normals) {
    ContextSelector selector(cc);
    std::vector<int> packed;
    for (const PairRandomKey& k : keys)
        packed.insert(packed.end(), {(int) k.stream, (int) (uint32_t) (uint64_t) k.step, (int) (uint32_t) ((uint64_t) k.step >> 32),
                                     k.i, k.j});
    ComputeArray keyArray, wordArray, normalArray;
    keyArray.initialize<int>(cc, packed.size(), "dpdCheckKeys");
    keyArray.upload(packed);
    wordArray.initialize<uint32_t>(cc, 4 * keys.size(), "dpdCheckWords");
    normalArray.initialize<float>(cc, keys.size(), "dpdCheckNormals");
    ComputeProgram program = compileDPDProgram(cc, {CommonDPDKernelSources::philox, CommonDPDKernelSources::pairRandomCheck});
    ComputeKernel kernel = program->createKernel("drawPairRandom");
    kernel->addArg((int) keys.size());
    kernel->addArg(seed);
    kernel->addArg(keyArray);
    kernel->addArg(wordArray);
    kernel->addArg(normalArray);
    kernel->execute(keys.size());
    wordArray.download(words);
    normalArray.download(normals);
}
