#ifndef OPENMMDPD_STEPSTATE_H_
#define OPENMMDPD_STEPSTATE_H_

#include "openmm/OpenMMException.h"
#include "openmm/Vec3.h"
#include <cstdint>
#include <iosfwd>
#include <string>
#include <vector>

namespace DPDPlugin {

class CheckpointReader;
class DPDPairParameters;

/**
 * A step stopped because the simulation blew up or crossed the instability threshold.  The
 * Context keeps what the stopped step made, and its time and step count are that step's
 * (DynamicsStepKernel advances them if the step stopped before it did), so the Context is
 * one consistent state and stepping again goes on from it.
 */
class StepStopped : public OpenMM::OpenMMException {
public:
    explicit StepStopped(const std::string& message) : OpenMM::OpenMMException(message) {}
};

/** A step that moves a particle farther than this many thermostat cutoffs has blown up. */
constexpr double MAX_MOVE_PER_STEP = 5.0;

/**
 * What every platform's step kernel carries from one step to the next: the force at the
 * current state (what that force is depends on the integrator) and whether it still holds.
 * Positions, velocities or parameters set from outside invalidate it.  Right after a
 * checkpoint was loaded OpenMM reports the restored state as set from outside too: then the
 * carried force is kept if the state is still the restored one when the next step starts.
 */
class CarriedForce {
public:
    explicit CarriedForce(int numParticles) : force(numParticles) {}
    std::vector<OpenMM::Vec3> force;
    void invalidate();
    /** Call at the start of a step: whether `force` still holds for these positions and velocities. */
    bool isValid(const std::vector<OpenMM::Vec3>& positions, const std::vector<OpenMM::Vec3>& velocities);
    void setValid() { valid = true; }
    /** Write the seed in use and the force, in binary so that a continuation is bit-exact. */
    void write(std::ostream& stream, uint32_t seed) const;
    /**
     * Read what write() wrote, for a Context now at these positions and velocities (the
     * restored ones); returns the seed.  Meant for a fresh CarriedForce that replaces the
     * one in use once the whole checkpoint has been read.
     */
    uint32_t read(CheckpointReader& reader, const std::vector<OpenMM::Vec3>& positions,
                  const std::vector<OpenMM::Vec3>& velocities);

private:
    bool valid = false, verifyRestoredState = false;
    std::vector<OpenMM::Vec3> restoredPositions, restoredVelocities;
};

/** Whether values[begin, end) are all finite (checkFinite's test, by range: for callers that test ranges in parallel). */
bool allFinite(const std::vector<OpenMM::Vec3>& values, size_t begin, size_t end);
/** Stops a run with "<name>: the simulation blew up at step N: ..." if a value is not finite. */
void checkFinite(const std::vector<OpenMM::Vec3>& values, const char* what, long long step, const std::string& name);
/** The same for values[k] of particle particles[k]. */
void checkFinite(const std::vector<OpenMM::Vec3>& values, const std::vector<int>& particles, const char* what, long long step,
                 const std::string& name);
/**
 * Staggered schemes: stops a run if the fast forces (`forces`, on every particle) are non-zero
 * on a particle i outside the polymer (polymerIndex[i] < 0), which would not feel them.
 */
void checkOutsidePolymer(const std::vector<OpenMM::Vec3>& forces, const std::vector<int>& polymerIndex, long long step,
                         const std::string& name);
/**
 * Ends a step: stops a run with "... blew up at step N ..." if a velocity is not finite, and,
 * if the parameters' instability threshold is on (and kT > 0), with "... unstable at step
 * N ..." if a particle's kinetic energy exceeds that many kT.  One pass does both.
 */
void checkVelocities(const std::vector<OpenMM::Vec3>& velocities, const DPDPairParameters& parameters, long long step,
                     const std::string& name);
/** Whether particles [begin, end) pass checkVelocities (its test, by range). */
bool velocitiesPass(const std::vector<OpenMM::Vec3>& velocities, const DPDPairParameters& parameters, size_t begin, size_t end);
/** Stops a run if the largest squared move of a step, maxMove2, exceeds MAX_MOVE_PER_STEP cutoffs. */
void checkMove(double maxMove2, double cutoff, long long step, const std::string& name);

} // namespace DPDPlugin

#endif
