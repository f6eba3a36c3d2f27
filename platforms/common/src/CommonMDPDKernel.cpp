#include "openmmdpd/CommonMDPDKernel.h"
#include "openmmdpd/ExcludedPairs.h"
#include "openmmdpd/MDPDParameters.h"
#include "CommonDPDKernelSources.h"
#include "openmm/common/ContextSelector.h"
#include <algorithm>

using namespace DPDPlugin;
using namespace OpenMM;

namespace {
// Where the force kernel's cell-list arguments start, and those after them.
constexpr int FORCE_CELL_ARGS = 16, FORCE_VIRIAL_ONLY_ARG = FORCE_CELL_ARGS + CommonCellList::NUM_ARGS,
              FORCE_VIRIAL_ROWS_ARG = FORCE_VIRIAL_ONLY_ARG + 1;
} // namespace

void CommonMDPDKernel::initialize(const System& system, const MDPDForce& force) {
    const std::string owner = "MDPDForce on the " + getPlatform().getName() + " platform";
    ContextSelector selector(cc);
    const int n = std::max(cc.getNumAtoms(), 1);
    atomType.initialize<int>(cc, n, "mdpdType");
    density.initialize(cc, n, mixedIsDouble(cc) ? sizeof(double) : sizeof(float), "mdpdDensity");
    uploadPartnerLists(cc, cc.getNumAtoms(), exclusionPairs(force), exclusionStart, exclusions, "mdpdExclusions");
    setParameters(force);
    ComputeProgram program = compileDPDProgram(cc, {CommonDPDKernelSources::cellList, CommonDPDKernelSources::mdpd});
    cells.reset(new CommonCellList(cc, program, owner, force.usesPeriodicBoundaryConditions()));
    createKernels(program);
}

void CommonMDPDKernel::createKernels(ComputeProgram& program) {
    ArrayInterface& posqCorrection = cc.getUseMixedPrecision() ? cc.getPosqCorrection() : cc.getPosq();
    densityKernel = program->createKernel("mdpdDensity");
    densityKernel->addArg(cc.getNumAtoms());
    addArrayArgs(densityKernel, {&cc.getPosq(), &posqCorrection, &cc.getAtomIndexArray(), &exclusionStart, &exclusions});
    densityKernel->addArg();  // densityParams: set per call
    densityKernel->addArg(density);
    for (int k = 0; k < CommonCellList::NUM_ARGS; k++)
        densityKernel->addArg();  // the cell list's
    forceKernel = program->createKernel("mdpdForce");
    forceKernel->addArg(cc.getNumAtoms());
    forceKernel->addArg(cc.getPaddedNumAtoms());
    forceKernel->addArg();  // the number of threads: set per call
    addArrayArgs(forceKernel, {&cc.getPosq(), &posqCorrection, &cc.getAtomIndexArray(), &atomType});
    for (int k = 0; k < 4; k++)
        forceKernel->addArg();  // numTypes, typeParams, typeB, densityParams: set per call
    addArrayArgs(forceKernel, {&density, &exclusionStart, &exclusions, &cc.getLongForceBuffer(), &cc.getEnergyBuffer()});
    for (int k = 0; k < CommonCellList::NUM_ARGS; k++)
        forceKernel->addArg();  // the cell list's
    virialRows.initialize(cc, 1, mixedIsDouble(cc) ? sizeof(double) : sizeof(float), "mdpdVirialRows");
    forceKernel->addArg();  // virialOnly: set per call
    forceKernel->addArg(virialRows);
}

void CommonMDPDKernel::setParameters(const MDPDForce& force) {
    const int n = cc.getNumAtoms();
    const MDPDParameters parameters(n, force);
    const TypePairTable& table = parameters.getTable();
    std::vector<int> types(std::max(n, 1), 0);
    for (int a = 0; a < n; a++)
        types[a] = table.typeOf(a);
    atomType.upload(types);
    std::vector<double> rows;
    for (int t = 0; t < table.getNumTypes() * table.getNumTypes(); t++)
        rows.insert(rows.end(), {table.value(t), table.cutoff(t), table.inverseCutoff(t), table.cutoff2(t)});
    uploadMixed4(cc, typeParams, rows, "mdpdTypeParams");
    uploadMixed(cc, typeB, parameters.getTypeBs(), "mdpdTypeB");
    const double rd = parameters.getDensityCutoff();
    const double values[4] = {parameters.getDensityNorm(), parameters.getInverseDensityCutoff(), rd * rd, parameters.getEnergyFactor()};
    std::copy(values, values + 4, densityParams);
    maxCutoff = table.getMaxCutoff();
    numTypes = table.getNumTypes();
}

int CommonMDPDKernel::run(bool virialOnly) {
    cells->build(maxCutoff);
    setMixed4Arg(cc, densityKernel, 6, densityParams);
    cells->setArgs(densityKernel, 8);
    densityKernel->execute(cc.getNumAtoms());
    // One energy slot per thread, as CommonSoftRepulsionKernel.
    const int energyThreads = std::min((int) cc.getEnergyBuffer().getSize(), std::max(cc.getNumAtoms(), 1));
    if (virialOnly && (int) virialRows.getSize() != 6 * energyThreads) {
        virialRows.resize(6 * energyThreads);
        forceKernel->setArg(FORCE_VIRIAL_ROWS_ARG, virialRows);
    }
    if (virialOnly)
        cc.clearBuffer(virialRows);
    forceKernel->setArg(2, energyThreads);
    forceKernel->setArg(7, numTypes);
    forceKernel->setArg(8, typeParams);
    forceKernel->setArg(9, typeB);
    setMixed4Arg(cc, forceKernel, 10, densityParams);
    cells->setArgs(forceKernel, FORCE_CELL_ARGS);
    forceKernel->setArg(FORCE_VIRIAL_ONLY_ARG, virialOnly ? 1 : 0);
    forceKernel->execute(energyThreads);
    return energyThreads;
}

double CommonMDPDKernel::execute(ContextImpl& context, bool includeForces, bool includeEnergy) {
    ContextSelector selector(cc);
    run(false);
    return 0.0;  // the energy is in OpenMM's energy buffer
}

void CommonMDPDKernel::copyParametersToContext(ContextImpl& context, const MDPDForce& force) {
    ContextSelector selector(cc);
    setParameters(force);
}

std::array<double, 6> CommonMDPDKernel::computeVirial(ContextImpl& context) {
    ContextSelector selector(cc);
    return sumVirialRows(cc, virialRows, run(true));
}
