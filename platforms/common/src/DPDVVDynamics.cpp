#include "openmmdpd/DPDVVDynamics.h"
#include "openmm/OpenMMException.h"
#include "ReferencePlatform.h"
#include <algorithm>
#include <cmath>
#include <istream>
#include <ostream>
#include <sstream>

using namespace DPDPlugin;
using OpenMM::Vec3;

namespace {

OpenMM::ReferencePlatform::PlatformData& platformData(OpenMM::ContextImpl& context) {
    return *static_cast<OpenMM::ReferencePlatform::PlatformData*>(context.getPlatformData());
}

} // namespace

DPDVVDynamics::DPDVVDynamics(const OpenMM::System& system, const DPDVVIntegrator& integrator, ParallelExecutor& executor) :
        executor(executor), thermostat(system, integrator, executor), forcesValid(false), verifyRestoredState(false) {
    const int n = system.getNumParticles();
    for (auto* v : {&force, &conservative, &dissipative, &random, &predicted, &velocityNoFD})
        v->resize(n);
    workerSums.resize(executor.getNumWorkers());
}

void DPDVVDynamics::checkFinite(const std::vector<Vec3>& values, const char* what, long long step) const {
    for (size_t i = 0; i < values.size(); i++)
        if (!(std::isfinite(values[i][0]) && std::isfinite(values[i][1]) && std::isfinite(values[i][2]))) {
            std::ostringstream message;
            message << "DPDVVIntegrator: the simulation blew up at step " << step << ": particle " << i << " has a non-finite "
                    << what << ". Reduce the step size, or check the starting configuration and the forces.";
            throw OpenMM::OpenMMException(message.str());
        }
}

void DPDVVDynamics::checkPositions(const std::vector<Vec3>& positions, long long step) const {
    checkFinite(positions, "position", step);
    // A particle that crossed several thermostat cutoffs in one step has left the regime
    // in which any of these schemes means anything (and would corrupt the pair search).
    const double limit = MAX_MOVE_PER_STEP * thermostat.getParameters().getMaxCutoff();
    double maxMove2 = 0;
    for (double m : workerSums)
        maxMove2 = std::max(maxMove2, m);
    if (maxMove2 > limit * limit) {
        std::ostringstream message;
        message << "DPDVVIntegrator: the simulation blew up at step " << step << ": a particle moved " << std::sqrt(maxMove2)
                << " nm in one step (more than " << MAX_MOVE_PER_STEP << " thermostat cutoffs). Reduce the step size, or check "
                << "the starting configuration and the forces.";
        throw OpenMM::OpenMMException(message.str());
    }
}

double DPDVVDynamics::sumMV2(const std::vector<Vec3>& velocities) const {
    const std::vector<double>& mass = thermostat.getParameters().getMasses();
    DPDVVDynamics* self = const_cast<DPDVVDynamics*>(this);
    executor.execute([&](int w) {
        size_t begin, end;
        executor.range(w, velocities.size(), begin, end);
        double sum = 0;
        for (size_t i = begin; i < end; i++)
            sum += mass[i] * velocities[i].dot(velocities[i]);
        self->workerSums[w] = sum;
    });
    double total = 0;
    for (double s : workerSums)
        total += s;
    return total;
}

double DPDVVDynamics::computeKineticEnergy(OpenMM::ContextImpl& context) const {
    return 0.5 * sumMV2(*platformData(context).velocities);
}

void DPDVVDynamics::computeConservativeAndPairs(OpenMM::ContextImpl& context, const DPDVVIntegrator& integrator, long long step) {
    OpenMM::ReferencePlatform::PlatformData& data = platformData(context);
    context.calcForcesAndEnergy(true, false, integrator.getIntegrationForceGroups());
    conservative = *data.forces;
    checkFinite(conservative, "conservative force", step);
    Vec3 box[3];
    context.getPeriodicBoxVectors(box[0], box[1], box[2]);
    thermostat.updatePairs(*data.positions, box);
}

void DPDVVDynamics::computeInitialForce(OpenMM::ContextImpl& context, const DPDVVIntegrator& integrator) {
    OpenMM::ReferencePlatform::PlatformData& data = platformData(context);
    const long long step = data.stepCount;
    computeConservativeAndPairs(context, integrator, step);
    thermostat.compute(DissipativeTerm | RandomTerm, *data.velocities, step, integrator.getStepSize(), dissipative, dissipative);
    for (size_t i = 0; i < force.size(); i++)
        force[i] = conservative[i] + dissipative[i];
    forcesValid = true;
}

void DPDVVDynamics::step(OpenMM::ContextImpl& context, const DPDVVIntegrator& integrator) {
    OpenMM::ReferencePlatform::PlatformData& data = platformData(context);
    std::vector<Vec3>& r = *data.positions;
    std::vector<Vec3>& v = *data.velocities;
    const std::vector<double>& invMass = thermostat.getParameters().getInverseMasses();
    const size_t n = r.size();
    const double dt = integrator.getStepSize();
    const long long next = data.stepCount + 1;
    if (!restoredPositions.empty()) {
        if (verifyRestoredState && (r != restoredPositions || v != restoredVelocities))
            forcesValid = false;
        restoredPositions.clear();
        restoredVelocities.clear();
    }
    if (!forcesValid)
        computeInitialForce(context, integrator);

    if (integrator.getVariant() == DPDVVIntegrator::GrootWarren) {
        const double lambda = integrator.getLambda();
        // r += dt v + dt^2/(2m) F ;  v~ = v + lambda dt F/m
        executor.execute([&](int w) {
            size_t begin, end;
            executor.range(w, n, begin, end);
            double maxMove2 = 0;
            for (size_t i = begin; i < end; i++) {
                const Vec3 move = v[i] * dt + force[i] * (0.5 * dt * dt * invMass[i]);
                r[i] += move;
                maxMove2 = std::max(maxMove2, move.dot(move));
                predicted[i] = v[i] + force[i] * (lambda * dt * invMass[i]);
            }
            workerSums[w] = maxMove2;
        });
        checkPositions(r, next);
        // F(t+dt) = FC(r) + FD(r, v~) + FR(r)
        computeConservativeAndPairs(context, integrator, next);
        thermostat.compute(DissipativeTerm | RandomTerm, predicted, next, dt, dissipative, dissipative);
        // v += dt/(2m) [F + F(t+dt)]
        executor.execute([&](int w) {
            size_t begin, end;
            executor.range(w, n, begin, end);
            for (size_t i = begin; i < end; i++) {
                Vec3 newForce = conservative[i] + dissipative[i];
                v[i] += (force[i] + newForce) * (0.5 * dt * invMass[i]);
                force[i] = newForce;
            }
        });
    }
    else {
        // (1) v += dt/(2m) (FC + FD + FR) ; (2) r += dt v
        executor.execute([&](int w) {
            size_t begin, end;
            executor.range(w, n, begin, end);
            double maxMove2 = 0;
            for (size_t i = begin; i < end; i++) {
                v[i] += force[i] * (0.5 * dt * invMass[i]);
                r[i] += v[i] * dt;
                maxMove2 = std::max(maxMove2, v[i].dot(v[i]) * dt * dt);
            }
            workerSums[w] = maxMove2;
        });
        checkPositions(r, next);
        // (3) FC(r), FD(r, v), FR(r) with the half-step v
        computeConservativeAndPairs(context, integrator, next);
        thermostat.compute(DissipativeTerm | RandomTerm, v, next, dt, dissipative, random);
        // (4a) v° = v + dt/(2m) (FC + FR)
        executor.execute([&](int w) {
            size_t begin, end;
            executor.range(w, n, begin, end);
            for (size_t i = begin; i < end; i++)
                velocityNoFD[i] = v[i] + (conservative[i] + random[i]) * (0.5 * dt * invMass[i]);
        });
        // (4b) v = v° + dt/(2m) FD ; (5) FD <- FD(r, v).  SC-VV repeats both until the
        // kinetic energy settles; DPD-VV does them once.
        const int iterations = (integrator.getVariant() == DPDVVIntegrator::SelfConsistent ? integrator.getMaxIterations() : 1);
        double previous = 0;
        for (int it = 0; it < iterations; it++) {
            executor.execute([&](int w) {
                size_t begin, end;
                executor.range(w, n, begin, end);
                for (size_t i = begin; i < end; i++)
                    v[i] = velocityNoFD[i] + dissipative[i] * (0.5 * dt * invMass[i]);
            });
            thermostat.compute(DissipativeTerm, v, next, dt, dissipative, random);
            if (iterations > 1) {
                const double kinetic = sumMV2(v);
                if (it > 0 && std::fabs(kinetic - previous) <= integrator.getTolerance() * kinetic)
                    break;
                previous = kinetic;
            }
        }
        executor.execute([&](int w) {
            size_t begin, end;
            executor.range(w, n, begin, end);
            for (size_t i = begin; i < end; i++)
                force[i] = conservative[i] + random[i] + dissipative[i];
        });
    }
    checkFinite(v, "velocity", next);
    data.stepCount = next;
    data.time += dt;
}

// The checkpoint holds what the platform's own checkpoint does not: the seed actually in
// use and the force carried into the next step, in binary so a continuation is bit-exact.
// (The pair list is a function of the positions alone, so it needs no saving.)
void DPDVVDynamics::createCheckpoint(std::ostream& stream) const {
    const uint32_t seed = thermostat.getSeed();
    const char valid = forcesValid ? 1 : 0;
    const uint64_t n = force.size();
    stream.write((const char*) &seed, sizeof(seed));
    stream.write(&valid, 1);
    stream.write((const char*) &n, sizeof(n));
    stream.write((const char*) force.data(), n * sizeof(Vec3));
}

void DPDVVDynamics::invalidateForces() {
    if (restoredPositions.empty())
        forcesValid = false;
    else
        verifyRestoredState = true;
}

void DPDVVDynamics::loadCheckpoint(OpenMM::ContextImpl& context, std::istream& stream) {
    uint32_t seed;
    char valid;
    uint64_t n;
    stream.read((char*) &seed, sizeof(seed));
    stream.read(&valid, 1);
    stream.read((char*) &n, sizeof(n));
    if (!stream || n != force.size())
        throw OpenMM::OpenMMException("DPDVVIntegrator: the checkpoint does not match this System");
    stream.read((char*) force.data(), n * sizeof(Vec3));
    if (!stream)
        throw OpenMM::OpenMMException("DPDVVIntegrator: the checkpoint is truncated");
    thermostat.setSeed(seed);
    forcesValid = (valid != 0);
    OpenMM::ReferencePlatform::PlatformData& data = platformData(context);
    restoredPositions = *data.positions;
    restoredVelocities = *data.velocities;
    verifyRestoredState = false;
}
