#include "openmmdpd/CommonDynamics.h"
#include "CommonDPDKernelSources.h"
#include "openmm/OpenMMException.h"
#include "openmm/common/ContextSelector.h"
#include "openmm/common/IntegrationUtilities.h"
#include "openmmdpd/DPDSoftRepulsionForce.h"
#include "openmmdpd/MDPDForce.h"
#include "openmmdpd/LeesEdwardsBoundary.h"
#include "openmmdpd/internal/ForceTerms.h"
#include "openmm/CustomBondForce.h"
#include <cmath>

using namespace DPDPlugin;
using namespace OpenMM;

namespace {

// Where the pair kernel's cell-list arguments start, and those after them.
constexpr int PAIR_CELL_ARGS = 19, PAIR_VIRIAL_TERMS_ARG = PAIR_CELL_ARGS + CommonCellList::NUM_ARGS,
              PAIR_VIRIAL_ROWS_ARG = PAIR_VIRIAL_TERMS_ARG + 2, PAIR_IMAGE_VELOCITY_ARG = PAIR_VIRIAL_TERMS_ARG + 3,
              PAIR_TRANSVERSE_ARG = PAIR_VIRIAL_TERMS_ARG + 4;

[[noreturn]] void refuse(const DPDThermostatIntegrator& integrator, const std::string& platform, const std::string& what) {
    throw OpenMMException(std::string(integrator.className()) + ": " + what + " is not supported on the " + platform +
                          " platform; use the Reference or CPU platform");
}

/**
 * OpenMM compiles its own device kernels for the box the Context was made with: for a
 * rectangular one, a periodic force of its own would ignore the tilt of a sheared box, or of
 * the pressure tensor's strains.  A System made with a triclinic box has kernels that take any
 * box.  (Our own pair forces take the box's tilt; an empty CustomBondForce, which only makes a
 * System periodic, has nothing to compute.)
 */
void refusePeriodicForces(const System& system, const DPDThermostatIntegrator& integrator, const std::string& platform) {
    Vec3 a, b, c;
    system.getDefaultPeriodicBoxVectors(a, b, c);
    if (b[0] != 0 || c[0] != 0 || c[1] != 0)
        return;
    for (int k = 0; k < system.getNumForces(); k++) {
        const Force& force = system.getForce(k);
        const CustomBondForce* bonds = dynamic_cast<const CustomBondForce*>(&force);
        if (!force.usesPeriodicBoundaryConditions() || dynamic_cast<const DPDSoftRepulsionForce*>(&force) != nullptr ||
            dynamic_cast<const MDPDForce*>(&force) != nullptr || (bonds != nullptr && bonds->getNumBonds() == 0))
            continue;
        refuse(integrator, platform, "Lees-Edwards shear or the pressure tensor with OpenMM's periodic " + force.getName() +
               " (force " + std::to_string(k) + ") in a System whose default box is rectangular (OpenMM's device kernels "
               "then take only such a box; give the System a tilted default box, e.g. b = (0.1 nm, Ly, 0))");
    }
}

bool hasVirtualSite(const System& system) {
    for (int i = 0; i < system.getNumParticles(); i++)
        if (system.isVirtualSite(i))
            return true;
    return false;
}

} // namespace

void CommonDynamics::refuseUnsupported(const System& system, const DPDThermostatIntegrator& integrator, const std::string& platform) {
    if (integrator.getShearRate() != 0 || integrator.getPressureTensorEnabled())
        refusePeriodicForces(system, integrator, platform);
}

CommonDynamics::CommonDynamics(ComputeContext& cc, const System& system, const DPDThermostatIntegrator& integrator,
                               const std::string& platform, const std::vector<std::string>& ruleSources, bool withPairForces) :
        cc(cc), name(std::string(integrator.className()) + " on the " + platform + " platform"), parameters(system, integrator),
        random(PairRandom::seedFor(integrator.getRandomNumberSeed())), carried(system.getNumParticles()) {
    ContextSelector selector(cc);
    hasVirtualSites = hasVirtualSite(system);
    hasConstraints = (system.getNumConstraints() > 0);
    const int n = std::max(numAtoms(), 1);
    atomType.initialize<int>(cc, n, "dpdAtomType");
    velocity.initialize(cc, n, mixedIsDouble(cc) ? 4 * sizeof(double) : 4 * sizeof(float), "dpdVelocity");
    carriedForce.initialize<long long>(cc, 3 * n, "dpdCarriedForce");
    status.initialize<int>(cc, 4, "dpdStatus");
    status.upload(std::vector<int>(4, 0));
    moveValue.initialize<float>(cc, 1, "dpdMoveValue");
    std::vector<std::string> sources = {CommonDPDKernelSources::philox, CommonDPDKernelSources::cellList,
                                        CommonDPDKernelSources::positionStrain, CommonDPDKernelSources::leesEdwards};
    if (withPairForces) {
        fd.initialize<long long>(cc, 3 * n, "dpdDissipativeForce");
        fr.initialize<long long>(cc, 3 * n, "dpdRandomForce");
        sources.push_back(CommonDPDKernelSources::dpdPairs);
    }
    sources.insert(sources.end(), ruleSources.begin(), ruleSources.end());
    program = compileDPDProgram(cc, sources);
    strain.reset(new CommonPositionStrain(cc, program));
    virialRows.initialize(cc, 1, mixedIsDouble(cc) ? sizeof(double) : sizeof(float), "dpdVirialRows");
    uploadParameters();
    gatherKernel = program->createKernel("gatherVelocities");
    gatherKernel->addArg(numAtoms());
    gatherKernel->addArg(cc.getVelm());
    gatherKernel->addArg(cc.getAtomIndexArray());
    gatherKernel->addArg(velocity);
    createSlideKernels(system);
    createConstraintKernel();
    if (withPairForces) {
        cells.reset(new CommonCellList(cc, program, name, system.usesPeriodicBoundaryConditions(), true));
        createPairKernels();
    }
}

void CommonDynamics::createSlideKernels(const System& system) {
    std::vector<int> start(1, 0), atoms;
    for (const std::vector<int>& molecule : findMolecules(system)) {
        atoms.insert(atoms.end(), molecule.begin(), molecule.end());
        start.push_back((int) atoms.size());
    }
    uploadInts(cc, moleculeStart, start, "dpdMoleculeStart");
    uploadInts(cc, moleculeAtoms, atoms, "dpdMoleculeAtoms");
    slotOf.initialize<int>(cc, std::max(numAtoms(), 1), "dpdSlotOf");
    findSlotsKernel = program->createKernel("findSlots");
    findSlotsKernel->addArg(numAtoms());
    addArrayArgs(findSlotsKernel, {&cc.getAtomIndexArray(), &slotOf});
    ArrayInterface& posqCorrection = cc.getUseMixedPrecision() ? cc.getPosqCorrection() : cc.getPosq();
    slideKernel = program->createKernel("slideMolecules");
    slideKernel->addArg((int) start.size() - 1);
    addArrayArgs(slideKernel, {&moleculeStart, &moleculeAtoms, &slotOf, &cc.getPosq(), &posqCorrection, &cc.getVelm(), &velocity});
    for (int k = 0; k < 4; k++)
        slideKernel->addArg();  // jumpAlso, the box, 1/Ly, U: set per call
}

void CommonDynamics::createConstraintKernel() {
    driftMove.initialize(cc, hasConstraints ? std::max(numAtoms(), 1) : 1, mixedIsDouble(cc) ? 4 * sizeof(double) : 4 * sizeof(float),
                         "dpdDriftMove");
    if (!hasConstraints)
        return;
    ArrayInterface& posqCorrection = cc.getUseMixedPrecision() ? cc.getPosqCorrection() : cc.getPosq();
    constrainedDriftKernel = program->createKernel("applyConstrainedDrift");
    constrainedDriftKernel->addArg(numAtoms());
    addArrayArgs(constrainedDriftKernel, {&cc.getPosq(), &posqCorrection, &cc.getVelm(), &cc.getAtomIndexArray(),
                                          &cc.getIntegrationUtilities().getPosDelta(), &driftMove, &velocity});
    for (int k = 0; k < 2; k++)
        constrainedDriftKernel->addArg();  // 1/dt and the move bound: set per drift
    constrainedDriftKernel->addArg(status);
    constrainedDriftKernel->addArg(moveValue);
}

void CommonDynamics::addDriftArgs(ComputeKernel& kernel) {
    kernel->addArg(hasConstraints ? 1 : 0);
    kernel->addArg(cc.getIntegrationUtilities().getPosDelta());
    kernel->addArg(driftMove);
}

void CommonDynamics::constrainDrift(double dt, double tolerance) {
    if (!hasConstraints)
        return;
    cc.getIntegrationUtilities().applyConstraints(tolerance);
    setMixedArg(cc, constrainedDriftKernel, 8, 1 / dt);
    setMixedArg(cc, constrainedDriftKernel, 9, maxMove2());
    constrainedDriftKernel->execute(numAtoms());
}

void CommonDynamics::constrainVelocities(double tolerance) {
    if (!hasConstraints)
        return;
    cc.getIntegrationUtilities().applyVelocityConstraints(tolerance);
    gatherVelocities();
}

void CommonDynamics::finishDrift(double dt, bool jumpVelocity) {
    if (hasVirtualSites)
        cc.getIntegrationUtilities().computeVirtualSites();
    slide(dt, jumpVelocity);
}

void CommonDynamics::slide(double dt, bool jumpVelocity) {
    const double rate = parameters.getShearRate();
    if (rate == 0)
        return;
    Vec3 box[3];
    cc.getPeriodicBoxVectors(box[0], box[1], box[2]);
    const double Ly = box[1][1], U = LeesEdwardsBoundary::advanceOffset(box, rate, dt);
    cc.setPeriodicBoxVectors(box[0], box[1], box[2]);
    findSlotsKernel->execute(numAtoms());
    const double size[4] = {box[0][0], Ly, box[2][2], box[1][0]};
    slideKernel->setArg(8, jumpVelocity ? 1 : 0);
    setMixed4Arg(cc, slideKernel, 9, size);
    setMixedArg(cc, slideKernel, 10, 1 / Ly);
    setMixedArg(cc, slideKernel, 11, U);
    slideKernel->execute(std::max((int) moleculeStart.getSize() - 1, 1));
}

void CommonDynamics::updateParameters(const System& system, const DPDThermostatIntegrator& integrator) {
    parameters = DPDPairParameters(system, integrator);
    ContextSelector selector(cc);
    uploadParameters();
    if (cells) {
        pairKernel->setArg(6, parameters.getTable().getNumTypes());
        pairKernel->setArg(7, typeParams);
        setArrayArgs(pairKernel, 8, {&exceptionStart, &exceptionPartner, &exceptionFactor});
        pairKernel->setArg(PAIR_TRANSVERSE_ARG, parameters.hasTransverse() ? 1 : 0);
        pairKernel->setArg(PAIR_TRANSVERSE_ARG + 1, transverseParams);
    }
}

void CommonDynamics::uploadParameters() {
    const TypePairTable& table = parameters.getTable();
    std::vector<int> types(std::max(numAtoms(), 1), 0);
    for (int a = 0; a < numAtoms(); a++)
        types[a] = table.typeOf(a);
    atomType.upload(types);
    // Per type pair: friction (or collision rate), rc, the weight exponent s, rc^2.
    std::vector<double> rows;
    for (int t = 0; t < table.getNumTypes() * table.getNumTypes(); t++)
        rows.insert(rows.end(), {table.value(t), table.cutoff(t), table.exponent(t), table.cutoff2(t)});
    uploadMixed4(cc, typeParams, rows, "dpdTypeParams");
    // Per type pair: the transverse friction rate, its weight exponent (and two unused).
    rows.clear();
    for (int t = 0; t < table.getNumTypes() * table.getNumTypes(); t++)
        rows.insert(rows.end(), {table.transverseValue(t), table.transverseExponent(t), 0.0, 0.0});
    uploadMixed4(cc, transverseParams, rows, "dpdTransverseParams");
    // The thermostat exceptions by lower atom index; without any, every atom's list is empty.
    std::vector<int> start = parameters.getExceptionStart();
    if (start.empty())
        start.assign(numAtoms() + 1, 0);
    uploadInts(cc, exceptionStart, start, "dpdExceptionStart");
    uploadInts(cc, exceptionPartner, parameters.getExceptionPartner(), "dpdExceptionPartner");
    uploadMixed(cc, exceptionFactor, parameters.getExceptionFactor(), "dpdExceptionFactor");
}

void CommonDynamics::createPairKernels() {
    ArrayInterface& posqCorrection = cc.getUseMixedPrecision() ? cc.getPosqCorrection() : cc.getPosq();
    pairKernel = program->createKernel("dpdPairForces");
    pairKernel->addArg(numAtoms());
    pairKernel->addArg(cc.getPosq());
    pairKernel->addArg(posqCorrection);
    pairKernel->addArg(cc.getAtomIndexArray());
    pairKernel->addArg(velocity);
    pairKernel->addArg(atomType);
    pairKernel->addArg(parameters.getTable().getNumTypes());
    pairKernel->addArg(typeParams);
    addArrayArgs(pairKernel, {&exceptionStart, &exceptionPartner, &exceptionFactor});
    for (int k = 11; k < 17; k++)
        pairKernel->addArg();  // kT, 1/sqrt(dt), seed, step, terms: set per pass
    pairKernel->addArg(fd);
    pairKernel->addArg(fr);
    for (int k = 0; k < CommonCellList::NUM_ARGS; k++)
        pairKernel->addArg();  // the cell list's
    pairKernel->addArg();      // virialTerms: set per pass
    pairKernel->addArg(cc.getPaddedNumAtoms());
    pairKernel->addArg(virialRows);
    pairKernel->addArg();      // the image velocity U of shear: set per pass
    pairKernel->addArg(parameters.hasTransverse() ? 1 : 0);
    pairKernel->addArg(transverseParams);
    sumKernel = program->createKernel("sumForces");
    sumKernel->addArg(numAtoms());
    sumKernel->addArg(cc.getPaddedNumAtoms());
    sumKernel->addArg(cc.getAtomIndexArray());
    sumKernel->addArg(cc.getLongForceBuffer());
    sumKernel->addArg(fd);
    sumKernel->addArg(fr);
    sumKernel->addArg();
    sumKernel->addArg(carriedForce);
}

bool CommonDynamics::carriedIsValid(ContextImpl& context) {
    std::vector<Vec3> r, v;
    if (awaitingRestoreCheck) {
        context.getPositions(r);
        context.getVelocities(v);
        awaitingRestoreCheck = false;
    }
    return carried.isValid(r, v);
}

void CommonDynamics::gatherVelocities() {
    gatherKernel->execute(numAtoms());
}

void CommonDynamics::conservativeForce(ContextImpl& context, int groups) {
    context.calcForcesAndEnergy(true, false, groups);
}

void CommonDynamics::pairForces(long long step, double dt, int terms, bool rebuildCells, int virialTerms) {
    if (rebuildCells)
        cells->build(parameters.getMaxCutoff());
    setMixedArg(cc, pairKernel, 11, parameters.getKT());
    setMixedArg(cc, pairKernel, 12, 1 / std::sqrt(dt));
    pairKernel->setArg(13, (unsigned int) random.getSeed());
    pairKernel->setArg(14, (unsigned int) (uint64_t) step);
    pairKernel->setArg(15, (unsigned int) ((uint64_t) step >> 32));
    pairKernel->setArg(16, terms);
    cells->setArgs(pairKernel, PAIR_CELL_ARGS);
    pairKernel->setArg(PAIR_VIRIAL_TERMS_ARG, thermostatVirial != nullptr ? virialTerms : 0);
    Vec3 box[3];
    cc.getPeriodicBoxVectors(box[0], box[1], box[2]);
    setMixedArg(cc, pairKernel, PAIR_IMAGE_VELOCITY_ARG, parameters.getShearRate() * box[1][1]);
    pairKernel->execute(numAtoms());
}

void CommonDynamics::startThermostatVirial() {
    if (thermostatVirial != nullptr && clearVirialRows(cc.getPaddedNumAtoms()))
        pairKernel->setArg(PAIR_VIRIAL_ROWS_ARG, virialRows);
}

void CommonDynamics::finishThermostatVirial() {
    if (thermostatVirial != nullptr)
        addVirialRows(cc.getPaddedNumAtoms(), 1);
}

bool CommonDynamics::clearVirialRows(int rows) {
    const bool resized = ((int) virialRows.getSize() < 6 * rows);
    if (resized)
        virialRows.resize(6 * rows);
    cc.clearBuffer(virialRows);
    return resized;
}

void CommonDynamics::addVirialRows(int rows, double scale) {
    const std::vector<double> values = downloadMixed(cc, virialRows);
    for (int c = 0; c < 6; c++)
        for (int k = 0; k < rows; k++)
            (*thermostatVirial)[c] += scale * values[k + c * rows];
}

void CommonDynamics::sumIntoCarried(bool withDissipative) {
    sumForcesInto(carriedForce, withDissipative);
}

void CommonDynamics::sumForcesInto(ComputeArray& out, bool withDissipative) {
    sumKernel->setArg(6, withDissipative ? 1 : 0);
    sumKernel->setArg(7, out);
    sumKernel->execute(numAtoms());
}

void CommonDynamics::checkStatus(ContextImpl& context, long long step) {
    std::vector<int> flags;
    status.download(flags);
    if (flags[0] == 0 && flags[1] == 0 && flags[2] == 0)
        return;
    status.upload(std::vector<int>(4, 0));
    std::vector<Vec3> r, v;
    context.getPositions(r);
    context.getVelocities(v);
    checkFinite(r, "position", step, name);
    if (flags[1] != 0) {
        std::vector<float> move2;
        moveValue.download(move2);
        checkMove(move2[0], parameters.getMaxCutoff(), step, name);
    }
    checkVelocities(v, parameters, step, name);
}

void CommonDynamics::finishStep(double dt) {
    cc.setTime(cc.getTime() + dt);
    cc.setStepCount(cc.getStepCount() + 1);
    cc.reorderAtoms();
}

double CommonDynamics::velocityBound() const {
    const double threshold = parameters.getInstabilityThreshold(), kT = parameters.getKT();
    return threshold > 0 && kT > 0 ? 2 * threshold * kT : 1e30;
}

double CommonDynamics::maxMove2() const {
    const double limit = MAX_MOVE_PER_STEP * parameters.getMaxCutoff();
    return limit * limit;
}

double CommonDynamics::computeKineticEnergy(ContextImpl& context) {
    ContextSelector selector(cc);
    return cc.getIntegrationUtilities().computeKineticEnergy(0);
}

void CommonDynamics::createCheckpoint(std::ostream& stream) const {
    ContextSelector selector(cc);
    std::vector<long long> fixed;
    const_cast<ComputeArray&>(carriedForce).download(fixed);
    CarriedForce copy = carried;
    const int n = numAtoms();
    for (int a = 0; a < n; a++)
        for (int d = 0; d < 3; d++)
            copy.force[a][d] = fromFixedForce(fixed[a + d * n]);
    copy.write(stream, random.getSeed());
    saveExtraState(stream);
}

void CommonDynamics::loadCheckpoint(ContextImpl& context, CheckpointReader& reader) {
    CarriedForce loaded(numAtoms());
    std::vector<Vec3> r, v;
    context.getPositions(r);
    context.getVelocities(v);
    const uint32_t seed = loaded.read(reader, r, v);
    loadExtraState(reader);
    reader.expectEnd();
    const int n = numAtoms();
    std::vector<long long> fixed(3 * std::max(n, 1), 0);
    for (int a = 0; a < n; a++)
        for (int d = 0; d < 3; d++)
            fixed[a + d * n] = toFixedForce(loaded.force[a][d]);
    ContextSelector selector(cc);
    carriedForce.upload(fixed);
    commitExtraState();
    carried = std::move(loaded);
    random = PairRandom(seed);
    awaitingRestoreCheck = true;
}

void CommonDynamics::resetState() {
    carried = CarriedForce(numAtoms());
    awaitingRestoreCheck = false;
    resetExtraState();
}
