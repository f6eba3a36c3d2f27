#include "openmmdpd/StepState.h"
#include "openmmdpd/CheckpointIO.h"
#include "openmmdpd/PairParameters.h"
#include "openmm/OpenMMException.h"
#include <cmath>
#include <istream>
#include <limits>
#include <ostream>
#include <sstream>

using namespace DPDPlugin;
using OpenMM::Vec3;

void CarriedForce::invalidate() {
    if (restoredPositions.empty())
        valid = false;
    else
        verifyRestoredState = true;
}

bool CarriedForce::isValid(const std::vector<Vec3>& r, const std::vector<Vec3>& v) {
    if (!restoredPositions.empty()) {
        if (verifyRestoredState && (r != restoredPositions || v != restoredVelocities))
            valid = false;
        restoredPositions.clear();
        restoredVelocities.clear();
    }
    return valid;
}

void CarriedForce::write(std::ostream& stream, uint32_t seed) const {
    putField<uint32_t>(stream, seed);
    putField<char>(stream, valid ? 1 : 0);
    putVectors(stream, force);
}

uint32_t CarriedForce::read(CheckpointReader& reader, const std::vector<Vec3>& r, const std::vector<Vec3>& v) {
    const uint32_t seed = reader.take<uint32_t>("the random number seed");
    const char flag = reader.take<char>("the carried force's flag");
    if (flag != 0 && flag != 1)
        reader.damaged("the carried force's flag is " + std::to_string((int) flag) + ", not 0 or 1");
    reader.takeVectors(force, "the carried force");
    valid = (flag != 0);
    restoredPositions = r;
    restoredVelocities = v;
    verifyRestoredState = false;
    return seed;
}

namespace {

bool isFinite(const Vec3& x) {
    return std::isfinite(x[0]) && std::isfinite(x[1]) && std::isfinite(x[2]);
}

[[noreturn]] void blewUp(const std::string& name, long long step, const std::string& what) {
    std::ostringstream message;
    message << name << ": the simulation blew up at step " << step << ": " << what
            << ". Reduce the step size, or check the starting configuration and the forces.";
    throw StepStopped(message.str());
}

[[noreturn]] void unstable(const std::string& name, long long step, int particle, double energy, double threshold) {
    std::ostringstream message;
    message << name << ": the simulation is unstable at step " << step << ": particle " << particle << " has kinetic energy "
            << energy << " kT, above the instability threshold " << threshold
            << " kT. Reduce the step size, or check the starting configuration and the forces.";
    throw StepStopped(message.str());
}

/** m v^2 above this fails checkVelocities. */
double velocityBound(const DPDPairParameters& parameters) {
    // m v^2 <= bound fails for a non-finite velocity as well as for a particle over the
    // threshold, so the common case costs one comparison per particle.  With the sentinel
    // off, the bound is the largest double: only non-finite values (or |v| ~ 1e154) fail it.
    const double kT = parameters.getKT(), threshold = parameters.getInstabilityThreshold();
    return threshold > 0 && kT > 0 ? 2 * threshold * kT : std::numeric_limits<double>::max();
}

} // namespace

bool DPDPlugin::velocitiesPass(const std::vector<Vec3>& v, const DPDPairParameters& parameters, size_t begin, size_t end) {
    const std::vector<double>& mass = parameters.getMasses();
    const double bound = velocityBound(parameters);
    bool pass = true;
    for (size_t i = begin; i < end; i++)
        pass &= (mass[i] * v[i].dot(v[i]) <= bound);
    return pass;
}

void DPDPlugin::checkVelocities(const std::vector<Vec3>& v, const DPDPairParameters& parameters, long long step,
                                const std::string& name) {
    if (velocitiesPass(v, parameters, 0, v.size()))
        return;
    const std::vector<double>& mass = parameters.getMasses();
    const double kT = parameters.getKT(), threshold = parameters.getInstabilityThreshold(), bound = velocityBound(parameters);
    for (size_t i = 0; i < v.size(); i++) {
        const double mv2 = mass[i] * v[i].dot(v[i]);
        if (mv2 <= bound)
            continue;
        if (!isFinite(v[i]))
            blewUp(name, step, "particle " + std::to_string(i) + " has a non-finite velocity");
        if (threshold > 0 && kT > 0)
            unstable(name, step, (int) i, 0.5 * mv2 / kT, threshold);
    }
}

bool DPDPlugin::allFinite(const std::vector<Vec3>& values, size_t begin, size_t end) {
    bool finite = true;
    for (size_t i = begin; i < end; i++)
        finite &= isFinite(values[i]);
    return finite;
}

void DPDPlugin::checkFinite(const std::vector<Vec3>& values, const char* what, long long step, const std::string& name) {
    for (size_t i = 0; i < values.size(); i++)
        if (!isFinite(values[i]))
            blewUp(name, step, "particle " + std::to_string(i) + " has a non-finite " + what);
}

void DPDPlugin::checkFinite(const std::vector<Vec3>& values, const std::vector<int>& particles, const char* what, long long step,
                            const std::string& name) {
    for (size_t k = 0; k < particles.size(); k++)
        if (!isFinite(values[k]))
            blewUp(name, step, "particle " + std::to_string(particles[k]) + " has a non-finite " + what);
}

void DPDPlugin::checkOutsidePolymer(const std::vector<Vec3>& forces, const std::vector<int>& polymerIndex, long long step,
                                    const std::string& name) {
    for (size_t i = 0; i < forces.size(); i++)
        if (polymerIndex[i] < 0 && forces[i] != Vec3()) {
            std::ostringstream message;
            message << name << ": at step " << step << " the fast forces act on particle " << i << ", which is not a polymer "
                    << "particle; polymer particles are the only ones sub-cycled, so add it to the polymer particles, or move "
                    << "that force out of the fast force groups";
            throw OpenMM::OpenMMException(message.str());
        }
}

void DPDPlugin::checkMove(double maxMove2, double cutoff, long long step, const std::string& name) {
    // A particle that crossed several thermostat cutoffs in one step has left the regime in
    // which any of these schemes means anything (and would corrupt the pair search).
    const double limit = MAX_MOVE_PER_STEP * cutoff;
    if (maxMove2 > limit * limit) {
        std::ostringstream move;
        move << "a particle moved " << std::sqrt(maxMove2) << " nm in one step (more than " << MAX_MOVE_PER_STEP
             << " thermostat cutoffs)";
        blewUp(name, step, move.str());
    }
}
