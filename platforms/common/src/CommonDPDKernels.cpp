#include "openmmdpd/CommonDPDKernels.h"
#include "openmmdpd/ExcludedPairs.h"
#include "CommonDPDKernelSources.h"
#include "openmm/common/ContextSelector.h"
#include <algorithm>

using namespace DPDPlugin;
using namespace OpenMM;

namespace {
// Where the soft repulsion kernel's cell-list arguments start, and those after them.
constexpr int CELL_ARGS = 13, VIRIAL_ONLY_ARG = CELL_ARGS + CommonCellList::NUM_ARGS, VIRIAL_ROWS_ARG = VIRIAL_ONLY_ARG + 1;
} // namespace

void CommonSoftRepulsionKernel::initialize(const System& system, const DPDSoftRepulsionForce& force) {
    const std::string owner = "DPDSoftRepulsionForce on the " + getPlatform().getName() + " platform";
    ContextSelector selector(cc);
    atomType.initialize<int>(cc, std::max(cc.getNumAtoms(), 1), "dpdSoftType");
    uploadExclusions(force);
    setParameters(force);
    ComputeProgram program = compileDPDProgram(cc, {CommonDPDKernelSources::cellList, CommonDPDKernelSources::softRepulsion});
    cells.reset(new CommonCellList(cc, program, owner, force.usesPeriodicBoundaryConditions()));
    ArrayInterface& posqCorrection = cc.getUseMixedPrecision() ? cc.getPosqCorrection() : cc.getPosq();
    kernel = program->createKernel("softRepulsion");
    kernel->addArg(cc.getNumAtoms());
    kernel->addArg(cc.getPaddedNumAtoms());
    kernel->addArg();  // the number of threads: set per call
    addArrayArgs(kernel, {&cc.getPosq(), &posqCorrection, &cc.getAtomIndexArray(), &atomType});
    kernel->addArg();  // the number of types and their parameters: set per call
    kernel->addArg();
    addArrayArgs(kernel, {&exclusionStart, &exclusions, &cc.getLongForceBuffer(), &cc.getEnergyBuffer()});
    for (int k = 0; k < CommonCellList::NUM_ARGS; k++)
        kernel->addArg();  // the cell list's
    virialRows.initialize(cc, 1, mixedIsDouble(cc) ? sizeof(double) : sizeof(float), "dpdSoftVirialRows");
    kernel->addArg();  // virialOnly: set per call
    kernel->addArg(virialRows);
}

void CommonSoftRepulsionKernel::uploadExclusions(const DPDSoftRepulsionForce& force) {
    uploadPartnerLists(cc, cc.getNumAtoms(), exclusionPairs(force), exclusionStart, exclusions, "dpdSoftExclusions");
}

void CommonSoftRepulsionKernel::setParameters(const DPDSoftRepulsionForce& force) {
    std::vector<TypePairTable::Entry> entries(force.getNumTypePairs());
    for (int k = 0; k < force.getNumTypePairs(); k++) {
        TypePairTable::Entry& e = entries[k];
        force.getTypePairParameters(k, e.type1, e.type2, e.value, e.cutoff);
    }
    const int n = cc.getNumAtoms();
    const TypePairTable table(n, force.getParticleTypes(), force.getDefaultA(), force.getDefaultCutoff(), entries);
    std::vector<int> types(std::max(n, 1), 0);
    for (int a = 0; a < n; a++)
        types[a] = table.typeOf(a);
    atomType.upload(types);
    std::vector<double> rows;
    for (int t = 0; t < table.getNumTypes() * table.getNumTypes(); t++)
        rows.insert(rows.end(), {table.value(t), table.cutoff(t), table.inverseCutoff(t), table.cutoff2(t)});
    uploadMixed4(cc, typeParams, rows, "dpdSoftTypeParams");
    maxCutoff = table.getMaxCutoff();
    numTypes = table.getNumTypes();
}

double CommonSoftRepulsionKernel::execute(ContextImpl& context, bool includeForces, bool includeEnergy) {
    ContextSelector selector(cc);
    run(false);
    return 0.0;  // the energy is in OpenMM's energy buffer
}

int CommonSoftRepulsionKernel::run(bool virialOnly) {
    cells->build(maxCutoff);
    // One energy slot per thread: as many threads as OpenMM's energy buffer has slots (it is
    // made after the kernels are initialized).
    const int energyThreads = std::min((int) cc.getEnergyBuffer().getSize(), std::max(cc.getNumAtoms(), 1));
    if (virialOnly && (int) virialRows.getSize() != 6 * energyThreads) {
        virialRows.resize(6 * energyThreads);
        kernel->setArg(VIRIAL_ROWS_ARG, virialRows);
    }
    if (virialOnly)
        cc.clearBuffer(virialRows);
    kernel->setArg(2, energyThreads);
    kernel->setArg(7, numTypes);
    kernel->setArg(8, typeParams);
    cells->setArgs(kernel, CELL_ARGS);
    kernel->setArg(VIRIAL_ONLY_ARG, virialOnly ? 1 : 0);
    kernel->execute(energyThreads);
    return energyThreads;
}

void CommonSoftRepulsionKernel::copyParametersToContext(ContextImpl& context, const DPDSoftRepulsionForce& force) {
    ContextSelector selector(cc);
    setParameters(force);
}

std::array<double, 6> CommonSoftRepulsionKernel::computeVirial(ContextImpl& context) {
    ContextSelector selector(cc);
    return sumVirialRows(cc, virialRows, run(true));
}
