#include "openmmdpd/PairDynamics.h"
#include "openmmdpd/SoftRepulsionKernel.h"
#include "openmmdpd/internal/DPDSoftRepulsionForceImpl.h"
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
    fusedVersion = -1;  // whether the soft force can be fused depends on the thermostat cutoffs
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

SoftRepulsionKernel* PairDynamics::softForceToFuse(OpenMM::ContextImpl& context, int forceGroups) {
    // Checked again only when the force's parameters or the force groups change.
    if (fusedVersion >= 0 && forceGroups == fusedForceGroups && fusedSoftForce->getParametersVersion() == fusedVersion)
        return fusedSoftForce;
    fusedVersion = -1;
    fusedIsAlone = false;
    SoftRepulsionKernel* found = nullptr;
    int count = 0;
    for (OpenMM::ForceImpl* impl : context.getForceImpls()) {
        DPDSoftRepulsionForceImpl* soft = dynamic_cast<DPDSoftRepulsionForceImpl*>(impl);
        if (soft != nullptr && (forceGroups & (1 << soft->getOwner().getForceGroup())) != 0) {
            found = dynamic_cast<SoftRepulsionKernel*>(&soft->getKernel().getImpl());
            count++;
        }
    }
    if (count != 1 || found == nullptr || found->isPeriodic() != thermostat.getSearch().isPeriodic())
        return nullptr;
    // Every pair the force acts on must be in the thermostat's list: every particle takes
    // part in the thermostat, and no force cutoff exceeds the thermostat cutoff of the same
    // pair (checked over the pairs of (force type, thermostat type) classes).
    const DPDPairParameters& parameters = thermostat.getParameters();
    const TypePairTable& forceTable = found->getTable();
    const TypePairTable& thermostatTable = parameters.getTable();
    int othersInGroups = 0;
    for (OpenMM::ForceImpl* impl : context.getForceImpls())
        if ((forceGroups & (1 << impl->getOwner().getForceGroup())) != 0 && dynamic_cast<DPDSoftRepulsionForceImpl*>(impl) == nullptr)
            othersInGroups++;
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
    fusedSoftForce = found;
    fusedIsAlone = (othersInGroups == 0);
    fusedForceGroups = forceGroups;
    fusedVersion = found->getParametersVersion();
    return found;
}

void PairDynamics::computeConservativeAndPairs(OpenMM::ContextImpl& context, int forceGroups, long long step) {
    OpenMM::ReferencePlatform::PlatformData& data = platformData(context);
    softForceFromPairs = nullptr;
    conservativeIsZero = false;
    computeConservative(context, forceGroups);
    Vec3 box[3];
    context.getPeriodicBoxVectors(box[0], box[1], box[2]);
    // The soft force alone is the whole conservative force: its pair sums go straight there.
    std::vector<Vec3>& softOut = (conservativeIsZero ? conservative : softForce);
    softOut.resize(conservative.size());
    thermostat.updatePairs(*data.positions, box, softForceFromPairs, &softOut, wantsPairsBySlot());
    if (softForceFromPairs != nullptr && !conservativeIsZero)
        forEachParticle(conservative.size(), [&](size_t i) { conservative[i] += softForce[i]; });
    checkFinite(conservative, "conservative force", step);
}

void PairDynamics::computeForceInOnePass(OpenMM::ContextImpl& context, int forceGroups, const std::vector<Vec3>& velocities,
                                         long long step, double dt, std::vector<Vec3>& out) {
    const SoftRepulsionKernel* soft;
    const std::vector<Vec3>* base = prepareSlotPasses(context, forceGroups, step, soft);
    thermostat.sumBySlot(DissipativeTerm | RandomTerm, velocities, step, dt, soft, base, out);
}

const std::vector<Vec3>* PairDynamics::prepareSlotPasses(OpenMM::ContextImpl& context, int forceGroups, long long step,
                                                         const SoftRepulsionKernel*& soft) {
    softForceFromPairs = nullptr;
    conservativeIsZero = false;
    computeConservative(context, forceGroups);
    if (!conservativeIsZero)
        checkFinite(conservative, "conservative force", step);
    Vec3 box[3];
    context.getPeriodicBoxVectors(box[0], box[1], box[2]);
    thermostat.searchSlots(*platformData(context).positions, box);
    soft = softForceFromPairs;
    return conservativeIsZero ? nullptr : &conservative;
}

void PairDynamics::computeConservative(OpenMM::ContextImpl& context, int forceGroups) {
    SoftRepulsionKernel* soft = softForceToFuse(context, forceGroups);
    if (soft != nullptr && fusedIsAlone) {
        // Nothing else to evaluate: skip the Context's force evaluation (zeroing and summing
        // its buffers cost 5 % of a GW step at N = 32000), and leave `conservative` unset:
        // the pair pass writes the soft force over all of it, or it is not read.
        conservativeIsZero = true;
        softForceFromPairs = soft;
        return;
    }
    if (soft != nullptr) {
        soft->setDeferred(true);
        try {
            context.calcForcesAndEnergy(true, false, forceGroups);
        }
        catch (...) {
            soft->setDeferred(false);
            throw;
        }
        soft->setDeferred(false);
        softForceFromPairs = soft;
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
