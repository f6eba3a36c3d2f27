#include "openmmdpd/PairDynamics.h"
#include "openmmdpd/FusedPairForce.h"
#include "openmmdpd/internal/DPDSoftRepulsionForceImpl.h"
#include "openmmdpd/internal/MDPDForceImpl.h"
#include "openmm/OpenMMException.h"
#include "ReferencePlatform.h"
#include <cmath>
#include <istream>
#include <ostream>
#include <sstream>

using namespace DPDPlugin;
using OpenMM::Vec3;

PairDynamics::PairDynamics(const OpenMM::System& system, const DPDThermostatIntegrator& integrator, ParallelExecutor& executor,
                           int cellMultiple) :
        name(integrator.className()), executor(executor), thermostat(system, integrator, executor, cellMultiple),
        carried(system.getNumParticles()), force(carried.force), conservative(system.getNumParticles()),
        workerSums(executor.getNumWorkers()), motion(system), shear(system) {
}

void PairDynamics::checkFinite(const std::vector<Vec3>& values, const std::vector<int>& particles, bool indexedByParticle,
                               const char* what, long long step) const {
    if (!indexedByParticle) {
        DPDPlugin::checkFinite(values, particles, what, step, name);
        return;
    }
    std::vector<Vec3> listed(particles.size());
    for (size_t k = 0; k < particles.size(); k++)
        listed[k] = values[particles[k]];
    DPDPlugin::checkFinite(listed, particles, what, step, name);
}

void PairDynamics::finishStep(OpenMM::ReferencePlatform::PlatformData& data, double dt) const {
    const std::vector<Vec3>& v = *data.velocities;
    const DPDPairParameters& parameters = thermostat.getParameters();
    if (!passesEverywhere(v.size(), [&](size_t begin, size_t end) { return velocitiesPass(v, parameters, begin, end); }))
        checkVelocities(v, parameters, data.stepCount + 1, name);
    // The Context's counters are ours to advance (Simulation.currentStep reads them).
    data.stepCount++;
    data.time += dt;
}

void PairDynamics::checkMoves(long long step) const {
    double maxMove2 = 0;
    for (double m : workerSums)
        maxMove2 = std::max(maxMove2, m);
    checkMove(maxMove2, thermostat.getParameters().getMaxCutoff(), step, name);
}

void PairDynamics::updateParameters(const OpenMM::System& system, const DPDThermostatIntegrator& integrator) {
    thermostat.setParameters(system, integrator);
    fusedVersion = -1;  // whether the fused force can be fused depends on the thermostat cutoffs
    parametersChanged();
}

double PairDynamics::sumMV2(const std::vector<Vec3>& velocities, const std::vector<double>& mass) const {
    executor.execute([&](int w) {
        size_t begin, end;
        executor.range(w, velocities.size(), begin, end);
        double sum = 0;
        for (size_t i = begin; i < end; i++)
            sum += mass[i] * velocities[i].dot(velocities[i]);
        workerSums[w] = sum;
    });
    double total = 0;
    for (double s : workerSums)
        total += s;
    return total;
}

double PairDynamics::computeKineticEnergy(OpenMM::ContextImpl& context) const {
    return 0.5 * sumMV2(*platformData(context).velocities, thermostat.getParameters().getMasses());
}

namespace {

/** The kernel of a force that a thermostat pass can add (DPDSoftRepulsionForce, MDPDForce); null for any other force. */
FusedPairForce* fusableKernel(OpenMM::ForceImpl* impl) {
    if (DPDSoftRepulsionForceImpl* soft = dynamic_cast<DPDSoftRepulsionForceImpl*>(impl))
        return dynamic_cast<FusedPairForce*>(&soft->getKernel().getImpl());
    if (MDPDForceImpl* mdpd = dynamic_cast<MDPDForceImpl*>(impl))
        return dynamic_cast<FusedPairForce*>(&mdpd->getKernel().getImpl());
    return nullptr;
}

} // namespace

FusedPairForce* PairDynamics::pairForceToFuse(OpenMM::ContextImpl& context, int forceGroups) {
    // Checked again only when the force's parameters or the force groups change.
    if (fusedVersion >= 0 && forceGroups == fusedForceGroups && fusedForce->getParametersVersion() == fusedVersion)
        return fusedForce;
    fusedVersion = -1;
    fusedIsAlone = false;
    FusedPairForce* found = nullptr;
    int count = 0, othersInGroups = 0;
    for (OpenMM::ForceImpl* impl : context.getForceImpls()) {
        if ((forceGroups & (1 << impl->getOwner().getForceGroup())) == 0)
            continue;
        FusedPairForce* kernel = fusableKernel(impl);
        if (kernel != nullptr) {
            found = kernel;
            count++;
        }
        else
            othersInGroups++;
    }
    if (count != 1 || found->isPeriodic() != thermostat.getSearch().isPeriodic())
        return nullptr;
    // Every pair the force acts on must be in the thermostat's list: every particle takes
    // part in the thermostat, and no force cutoff exceeds the thermostat cutoff of the same
    // pair (checked over the pairs of (force type, thermostat type) classes).
    const DPDPairParameters& parameters = thermostat.getParameters();
    const TypePairTable& forceTable = found->getTable();
    const TypePairTable& thermostatTable = parameters.getTable();
    std::vector<std::pair<int, int>> classes;
    for (int i = 0; i < parameters.getNumParticles(); i++) {
        if (!parameters.getActive()[i])
            return nullptr;
        const std::pair<int, int> c(forceTable.typeOf(i), thermostatTable.typeOf(i));
        if (std::find(classes.begin(), classes.end(), c) == classes.end())
            classes.push_back(c);
    }
    for (const auto& a : classes)
        for (const auto& b : classes)
            if (forceTable.cutoff(forceTable.indexOfTypes(a.first, b.first)) >
                thermostatTable.cutoff(thermostatTable.indexOfTypes(a.second, b.second)))
                return nullptr;
    fusedForce = found;
    fusedIsAlone = (othersInGroups == 0);
    fusedForceGroups = forceGroups;
    fusedVersion = found->getParametersVersion();
    return found;
}

void PairDynamics::computeConservativeAndPairs(OpenMM::ContextImpl& context, int forceGroups, long long step) {
    OpenMM::ReferencePlatform::PlatformData& data = platformData(context);
    forceFromPairs = nullptr;
    conservativeIsZero = false;
    computeConservative(context, forceGroups);
    Vec3 box[3];
    context.getPeriodicBoxVectors(box[0], box[1], box[2]);
    // The fused force alone is the whole conservative force: its pair sums go straight there.
    std::vector<Vec3>& fusedOut = (conservativeIsZero ? conservative : fusedForceSum);
    fusedOut.resize(conservative.size());
    thermostat.updatePairs(*data.positions, box, forceFromPairs, &fusedOut, wantsPairsBySlot());
    if (forceFromPairs != nullptr && !conservativeIsZero)
        forEachParticle(conservative.size(), [&](size_t i) { conservative[i] += fusedForceSum[i]; });
    checkFinite(conservative, "conservative force", step);
}

void PairDynamics::computeForceInOnePass(OpenMM::ContextImpl& context, int forceGroups, const std::vector<Vec3>& velocities,
                                         long long step, double dt, std::vector<Vec3>& out) {
    const FusedPairForce* fused;
    const std::vector<Vec3>* base = prepareSlotPasses(context, forceGroups, step, fused);
    thermostat.sumBySlot(DissipativeTerm | RandomTerm, velocities, step, dt, fused, base, out);
}

const std::vector<Vec3>* PairDynamics::prepareSlotPasses(OpenMM::ContextImpl& context, int forceGroups, long long step,
                                                         const FusedPairForce*& fused) {
    forceFromPairs = nullptr;
    conservativeIsZero = false;
    computeConservative(context, forceGroups);
    if (!conservativeIsZero)
        checkFinite(conservative, "conservative force", step);
    Vec3 box[3];
    context.getPeriodicBoxVectors(box[0], box[1], box[2]);
    thermostat.searchSlots(*platformData(context).positions, box);
    fused = forceFromPairs;
    return conservativeIsZero ? nullptr : &conservative;
}

void PairDynamics::computeConservative(OpenMM::ContextImpl& context, int forceGroups) {
    FusedPairForce* fused = pairForceToFuse(context, forceGroups);
    if (fused != nullptr && fusedIsAlone) {
        // Nothing else to evaluate: skip the Context's force evaluation (zeroing and summing
        // its buffers cost 5 % of a GW step at N = 32000), and leave `conservative` unset:
        // the pair pass writes the fused force over all of it, or it is not read.
        conservativeIsZero = true;
        addForceFromPairs(context, fused);
        return;
    }
    if (fused != nullptr) {
        fused->setDeferred(true);
        try {
            context.calcForcesAndEnergy(true, false, forceGroups);
        }
        catch (...) {
            fused->setDeferred(false);
            throw;
        }
        fused->setDeferred(false);
        forceFromPairs = fused;
    }
    else
        context.calcForcesAndEnergy(true, false, forceGroups);
    conservative = *platformData(context).forces;
}

// The checkpoint holds what the platform's own checkpoint does not: the seed actually in
// use and the force carried into the next step, in binary so a continuation is bit-exact.
// (The pair list is a function of the positions alone, so it needs no saving.)
void PairDynamics::createCheckpoint(std::ostream& stream) const {
    carried.write(stream, thermostat.getSeed());
    saveExtraState(stream);
}

void PairDynamics::loadCheckpoint(OpenMM::ContextImpl& context, CheckpointReader& reader) {
    OpenMM::ReferencePlatform::PlatformData& data = platformData(context);
    CarriedForce loaded(force.size());
    const uint32_t seed = loaded.read(reader, *data.positions, *data.velocities);
    loadExtraState(reader);
    reader.expectEnd();
    commitExtraState();
    carried = std::move(loaded);
    thermostat.setSeed(seed);
    stateRestored();
}

void PairDynamics::resetState() {
    carried = CarriedForce(force.size());
    resetExtraState();
    stateRestored();
}
