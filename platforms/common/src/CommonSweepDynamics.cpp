#include "openmmdpd/CommonSweepDynamics.h"
#include "openmmdpd/ConstrainedPairImpulse.h"
#include "CommonDPDKernelSources.h"
#include "openmm/OpenMMException.h"
#include "openmm/common/ComputeVectorTypes.h"
#include "openmm/common/ContextSelector.h"
#include "openmm/common/IntegrationUtilities.h"

using namespace DPDPlugin;
using namespace OpenMM;

namespace {

std::vector<std::string> withSweepSources(std::vector<std::string> ruleSources) {
    ruleSources.insert(ruleSources.begin(),
                       {CommonDPDKernelSources::dpdvv, CommonDPDKernelSources::pairConstraints, CommonDPDKernelSources::sweep});
    return ruleSources;
}

} // namespace

CommonSweepDynamics::CommonSweepDynamics(ComputeContext& cc, const System& system, const DPDThermostatIntegrator& integrator,
                                         const std::string& platform, const std::vector<std::string>& ruleSources,
                                         bool withPairForces) :
        CommonDynamics(cc, system, integrator, platform, withSweepSources(ruleSources), withPairForces),
        scan(cc, program), grid(cc, program, name, system.usesPeriodicBoundaryConditions(), true) {
    ContextSelector selector(cc);
    const int n = std::max(numAtoms(), 1);
    position.initialize(cc, n, mixedIsDouble(cc) ? 4 * sizeof(double) : 4 * sizeof(float), "dpdSweepPosition");
    atomCell.initialize<int>(cc, n, "dpdSweepAtomCell");
    cellAtoms.initialize<int>(cc, n, "dpdSweepCellAtoms");
    // The arguments that change with the grid, the box or the step are set where they are used.
    const std::vector<std::pair<ComputeKernel*, std::pair<std::string, int>>> kernels = {
            {&assignKernel, {"sweepAssign", 11}}, {&clearKernel, {"clearCells", 2}}, {&fillKernel, {"fillCells", 5}},
            {&sortKernel, {"sweepSortCells", 3}}, {&colourKernel, {"sweepColour", 39}}, {&scatterKernel, {"scatterVelocities", 6}},
            {&kickDriftKernel, {"kickDrift", 14}}, {&conservativeKernel, {"takeConservativeForce", 9}}};
    for (const auto& k : kernels)
        *k.first = createKernelWithArgs(program, k.second.first, k.second.second);
    ArrayInterface& posqCorrection = cc.getUseMixedPrecision() ? cc.getPosqCorrection() : cc.getPosq();
    kickDriftKernel->setArg(0, numAtoms());
    kickDriftKernel->setArg(1, cc.getPosq());
    kickDriftKernel->setArg(2, posqCorrection);
    kickDriftKernel->setArg(3, cc.getVelm());
    kickDriftKernel->setArg(4, cc.getAtomIndexArray());
    kickDriftKernel->setArg(5, carriedForce);
    kickDriftKernel->setArg(9, status);
    kickDriftKernel->setArg(10, moveValue);
    kickDriftKernel->setArg(11, hasConstraints ? 1 : 0);
    kickDriftKernel->setArg(12, cc.getIntegrationUtilities().getPosDelta());
    kickDriftKernel->setArg(13, driftMove);
    conservativeKernel->setArg(0, numAtoms());
    conservativeKernel->setArg(1, cc.getPaddedNumAtoms());
    conservativeKernel->setArg(2, cc.getVelm());
    conservativeKernel->setArg(3, cc.getAtomIndexArray());
    conservativeKernel->setArg(4, cc.getLongForceBuffer());
    conservativeKernel->setArg(5, carriedForce);
    conservativeKernel->setArg(8, status);
    scatterKernel->setArg(0, numAtoms());
    scatterKernel->setArg(1, velocity);
    scatterKernel->setArg(2, cc.getAtomIndexArray());
    scatterKernel->setArg(3, cc.getVelm());
    scatterKernel->setArg(5, status);
    createConstraintClusters(system);
}

void CommonSweepDynamics::createConstraintClusters(const System& system) {
    std::vector<int> clusterOf(std::max(numAtoms(), 1), -1), start(1, 0), matrixStart(1, 0);
    std::vector<mm_int2> atoms;
    for (const std::vector<int>& cluster : findConstraintClusters(system)) {
        for (int k : cluster) {
            int a, b;
            double distance;
            system.getConstraintParameters(k, a, b, distance);
            atoms.push_back(mm_int2(a, b));
            clusterOf[a] = clusterOf[b] = (int) start.size() - 1;
        }
        start.push_back((int) atoms.size());
        matrixStart.push_back(matrixStart.back() + (int) (cluster.size() * cluster.size()));
    }
    numClusters = (int) start.size() - 1;
    uploadInts(cc, clusterOfAtom, clusterOf, "dpdClusterOf");
    uploadInts(cc, clusterStart, start, "dpdClusterStart");
    uploadInts(cc, clusterMatrixStart, matrixStart, "dpdClusterMatrixStart");
    constraintAtoms.initialize<mm_int2>(cc, std::max((int) atoms.size(), 1), "dpdConstraintAtoms");
    if (!atoms.empty())
        constraintAtoms.upload(atoms);
    const int mixedSize = mixedIsDouble(cc) ? sizeof(double) : sizeof(float);
    constraintDirection.initialize(cc, std::max((int) atoms.size(), 1), 4 * mixedSize, "dpdConstraintDirection");
    clusterMatrix.initialize(cc, std::max(matrixStart.back(), 1), mixedSize, "dpdClusterMatrix");
    factorKernel = program->createKernel("factorConstraintClusters");
    factorKernel->addArg(numClusters);
    addArrayArgs(factorKernel, {&clusterStart, &constraintAtoms, &position, &velocity, &clusterMatrixStart, &constraintDirection,
                                &clusterMatrix});
}

void CommonSweepDynamics::ensureCarriedForce(ContextImpl& context, int forceGroups) {
    if (!carriedIsValid(context)) {
        takeConservativeForce(context, forceGroups, 0);
        carried.setValid();
    }
}

void CommonSweepDynamics::kickDrift(double kick, double drift) {
    setMixedArg(cc, kickDriftKernel, 6, kick);
    setMixedArg(cc, kickDriftKernel, 7, drift);
    setMixedArg(cc, kickDriftKernel, 8, maxMove2());
    kickDriftKernel->execute(numAtoms());
    if (drift != 0) {
        constrainDrift(drift, constraintTolerance);
        finishDrift(drift, false);  // the sweeps gather the velocities afresh
    }
}

void CommonSweepDynamics::takeConservativeForce(ContextImpl& context, int forceGroups, double kick) {
    conservativeForce(context, forceGroups);
    setMixedArg(cc, conservativeKernel, 6, kick);
    setMixedArg(cc, conservativeKernel, 7, velocityBound());
    conservativeKernel->execute(numAtoms());
}

void CommonSweepDynamics::velocityVerlet(ContextImpl& context, int forceGroups, double dt) {
    kickDrift(0.5 * dt, dt);
    takeConservativeForce(context, forceGroups, 0.5 * dt);
    constrainVelocities(constraintTolerance);
}

void CommonSweepDynamics::buildGrid() {
    box = grid.current(parameters.getMaxCutoff(), "the thermostat cutoff");
    for (int k = 0; k < 3; k++) {
        // As ReferencePairList::bin: the same cells give the same pair order.  (An open grid's
        // to a rounding: the Reference divides by the extent, the device multiplies by its inverse.)
        numCells[k] = box.cellsAcross(k, parameters.getMaxCutoff());
        if (grid.isPeriodic() && numCells[k] >= 3)
            numCells[k] -= numCells[k] % 3;
    }
    // The Reference's grid cannot be widened: a grid too large to hold is an error.
    const long long numGridCells = (long long) numCells[0] * numCells[1] * numCells[2];
    if (numGridCells > MaxGridCells)
        throw OpenMMException(name + ": a sweep grid of " + std::to_string(numCells[0]) + " x " + std::to_string(numCells[1]) +
                              " x " + std::to_string(numCells[2]) + " cells of a cutoff, more than " + std::to_string(MaxGridCells) +
                              " (in an open System: has a particle escaped?)");
    const int total = (int) numGridCells;
    if (total != totalCells) {
        if (!cellCount.isInitialized()) {
            cellCount.initialize<int>(cc, total, "dpdSweepCellCount");
            cellStart.initialize<int>(cc, total + 1, "dpdSweepCellStart");
        }
        else {
            cellCount.resize(total);
            cellStart.resize(total + 1);
        }
        totalCells = total;
    }
    const mm_int4 cells(numCells[0], numCells[1], numCells[2], grid.isPeriodic() ? 1 : 0);
    ArrayInterface& posqCorrection = cc.getUseMixedPrecision() ? cc.getPosqCorrection() : cc.getPosq();
    clearKernel->setArg(0, total);
    clearKernel->setArg(1, cellCount);
    clearKernel->execute(total);
    assignKernel->setArg(0, numAtoms());
    setArrayArgs(assignKernel, 1, {&cc.getPosq(), &posqCorrection, &cc.getAtomIndexArray()});
    setMixed4Arg(cc, assignKernel, 4, box.origin);
    setMixed4Arg(cc, assignKernel, 5, box.rowX);
    setMixed4Arg(cc, assignKernel, 6, box.rowYZ);
    assignKernel->setArg(7, cells);
    setArrayArgs(assignKernel, 8, {&position, &atomCell, &cellCount});
    assignKernel->execute(numAtoms());
    scan.execute(total, cellCount, cellStart);
    fillKernel->setArg(0, numAtoms());
    setArrayArgs(fillKernel, 1, {&atomCell, &cellStart, &cellCount, &cellAtoms});
    fillKernel->execute(numAtoms());
    sortKernel->setArg(0, total);
    setArrayArgs(sortKernel, 1, {&cellStart, &cellAtoms});
    sortKernel->execute(total);
}

void CommonSweepDynamics::sweep(Rule rule, double h, double dt, PairRandom::Stream stream, PairRandom::Stream transverseStream,
                                long long step, bool reverse, bool partner) {
    gatherVelocities();
    buildGrid();
    if (numClusters > 0)
        factorKernel->execute(numClusters);
    colourKernel->setArg(1, reverse ? 1 : 0);
    colourKernel->setArg(2, (int) rule);
    setMixedArg(cc, colourKernel, 3, h);
    setMixedArg(cc, colourKernel, 4, parameters.getKT());
    colourKernel->setArg(5, (unsigned int) random.getSeed());
    colourKernel->setArg(6, (unsigned int) stream);
    colourKernel->setArg(7, (unsigned int) (uint64_t) step);
    colourKernel->setArg(8, (unsigned int) ((uint64_t) step >> 32));
    setArrayArgs(colourKernel, 9, {&position, &velocity, &atomType});
    colourKernel->setArg(12, parameters.getTable().getNumTypes());
    colourKernel->setArg(13, typeParams);
    setMixed4Arg(cc, colourKernel, 14, box.size);
    setMixed4Arg(cc, colourKernel, 15, box.inverse);
    setMixed4Arg(cc, colourKernel, 16, box.c);
    colourKernel->setArg(17, mm_int4(numCells[0], numCells[1], numCells[2], grid.isPeriodic() ? 1 : 0));
    setArrayArgs(colourKernel, 18, {&cellStart, &cellAtoms});
    colourKernel->setArg(20, partner ? 1 : 0);
    setArrayArgs(colourKernel, 21, {&exceptionStart, &exceptionPartner, &exceptionFactor});
    // As the Reference: an open grid is always coloured, a periodic one with 3 cells or more on every axis.
    const bool coloured = !grid.isPeriodic() || (numCells[0] >= 3 && numCells[1] >= 3 && numCells[2] >= 3);
    const int cellsPerColour = ((numCells[0] + 2) / 3) * ((numCells[1] + 2) / 3) * ((numCells[2] + 2) / 3);
    const int rows = (coloured && numClusters == 0 ? cellsPerColour : 1);  // with constraints: one work item (kernels/sweep.cc)
    const bool virial = (thermostatVirial != nullptr);
    if (virial)
        clearVirialRows(rows);
    colourKernel->setArg(24, virial ? 1 : 0);
    colourKernel->setArg(25, rows);
    colourKernel->setArg(26, virialRows);
    setMixedArg(cc, colourKernel, 27, parameters.getShearRate() * box.size[1]);
    colourKernel->setArg(28, (unsigned int) transverseStream);
    colourKernel->setArg(29, parameters.hasTransverse() ? 1 : 0);
    colourKernel->setArg(30, transverseParams);
    colourKernel->setArg(31, numClusters > 0 ? 1 : 0);
    setArrayArgs(colourKernel, 32, {&clusterOfAtom, &clusterStart, &constraintAtoms, &constraintDirection, &clusterMatrixStart,
                                    &clusterMatrix});
    for (int k = 0; k < (coloured ? 27 : 1); k++) {
        colourKernel->setArg(0, coloured ? (reverse ? 26 - k : k) : -1);
        colourKernel->execute(rows);
    }
    if (virial)
        addVirialRows(rows, 1 / dt);
    setMixedArg(cc, scatterKernel, 4, velocityBound());
    scatterKernel->execute(numAtoms());
    constrainVelocities(constraintTolerance);
}

void CommonShardlowDynamics::step(ContextImpl& context, const ShardlowIntegrator& integrator) {
    ContextSelector selector(cc);
    constraintTolerance = integrator.getConstraintTolerance();
    const double dt = integrator.getStepSize();
    const int forceGroups = integrator.getIntegrationForceGroups();
    // Every random number of the step is keyed by the step it starts from (but S2's second
    // sweep's); transverse friction's by the same steps, in streams of its own.
    const long long current = cc.getStepCount(), next = current + 1;
    ensureCarriedForce(context, forceGroups);
    const bool secondOrder = (integrator.getOrder() == 2);
    const double h = secondOrder ? 0.5 * dt : dt;
    // S1: sweep (dt) ; VV.  S2: sweep (dt/2) ; VV ; sweep (dt/2) in the reverse order, over
    // the pairs at the new positions, with the partners of the numbers the next step's first
    // sweep takes (as the Reference).
    sweep(ShardlowRule, h, dt, PairRandom::RandomForce, PairRandom::TransverseNoise, current, false);
    velocityVerlet(context, forceGroups, dt);
    if (secondOrder)
        sweep(ShardlowRule, h, dt, PairRandom::RandomForce, PairRandom::TransverseSecondSweep, next, true, true);
    checkStatus(context, next);
    finishStep(dt);
}

void CommonLoweAndersenDynamics::step(ContextImpl& context, const LoweAndersenIntegrator& integrator) {
    ContextSelector selector(cc);
    constraintTolerance = integrator.getConstraintTolerance();
    const double dt = integrator.getStepSize();
    const int forceGroups = integrator.getIntegrationForceGroups();
    const long long current = cc.getStepCount(), next = current + 1;
    ensureCarriedForce(context, forceGroups);
    if (integrator.getSplitting() == LoweAndersenIntegrator::Middle)
        middleStep(context, integrator);
    else {
        // B A A B O: VV ; the pair thermostat over dt, over the pairs at the new positions.
        velocityVerlet(context, forceGroups, dt);
        applyThermostat(integrator, current);
    }
    checkStatus(context, next);
    finishStep(dt);
}

void CommonLoweAndersenDynamics::middleStep(ContextImpl& context, const LoweAndersenIntegrator& integrator) {
    const double dt = integrator.getStepSize();
    const long long current = cc.getStepCount();
    // B B (the last step's closing half kick and this step's opening one) A ; O over dt at
    // the mid-step positions ; A ; F <- FC(r)
    kickDrift(dt, 0.5 * dt);
    applyThermostat(integrator, current);
    kickDrift(0, 0.5 * dt);
    takeConservativeForce(context, integrator.getIntegrationForceGroups(), 0);
}

void CommonLoweAndersenDynamics::applyThermostat(const LoweAndersenIntegrator& integrator, long long step) {
    const Rule rule = (integrator.getMethod() == LoweAndersenIntegrator::Lowe ? LoweRule : PairOrnsteinUhlenbeckRule);
    sweep(rule, integrator.getStepSize(), integrator.getStepSize(), PairRandom::PairThermalisation, PairRandom::TransverseNoise, step,
          false);
}
