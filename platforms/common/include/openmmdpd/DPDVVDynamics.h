#ifndef OPENMMDPD_DPDVVDYNAMICS_H_
#define OPENMMDPD_DPDVVDYNAMICS_H_

#include "openmmdpd/DPDThermostatForces.h"
#include "openmmdpd/DPDVVIntegrator.h"
#include "openmmdpd/ParallelExecutor.h"
#include "openmm/internal/ContextImpl.h"
#include <iosfwd>
#include <memory>

namespace DPDPlugin {

/** A step that moves a particle farther than this many thermostat cutoffs has blown up. */
constexpr double MAX_MOVE_PER_STEP = 5.0;

/**
 * The DPD velocity-Verlet family (algorithms.md section 1), written once over the
 * platform data that the Reference and CPU platforms share; the platforms differ only in
 * the executor (and the CPU platform's own conservative forces).
 */
class DPDVVDynamics {
public:
    DPDVVDynamics(const OpenMM::System& system, const DPDVVIntegrator& integrator, ParallelExecutor& executor);
    void step(OpenMM::ContextImpl& context, const DPDVVIntegrator& integrator);
    double computeKineticEnergy(OpenMM::ContextImpl& context) const;
    /**
     * Positions, velocities or parameters were set from outside.  Right after a checkpoint
     * was loaded, OpenMM reports the restored state this way too: then the carried force
     * is kept if the state is still the restored one when the next step starts.
     */
    void invalidateForces();
    void createCheckpoint(std::ostream& stream) const;
    void loadCheckpoint(OpenMM::ContextImpl& context, std::istream& stream);
    DPDThermostatForces& getThermostat() { return thermostat; }

private:
    /** FC <- the System's forces in the integration groups; the thermostat pairs at the same positions. */
    void computeConservativeAndPairs(OpenMM::ContextImpl& context, const DPDVVIntegrator& integrator, long long step);
    /** F <- FC + FD(v) + FR, at the current state (a start, or after outside changes). */
    void computeInitialForce(OpenMM::ContextImpl& context, const DPDVVIntegrator& integrator);
    /** Positions must be finite and no particle may have jumped (workerSums holds each worker's largest move^2). */
    void checkPositions(const std::vector<OpenMM::Vec3>& positions, long long step) const;
    void checkFinite(const std::vector<OpenMM::Vec3>& values, const char* what, long long step) const;
    double sumMV2(const std::vector<OpenMM::Vec3>& velocities) const;

    ParallelExecutor& executor;
    DPDThermostatForces thermostat;
    bool forcesValid, verifyRestoredState;
    std::vector<OpenMM::Vec3> restoredPositions, restoredVelocities;
    std::vector<OpenMM::Vec3> force, conservative, dissipative, random, predicted, velocityNoFD;
    std::vector<double> workerSums;
};

} // namespace DPDPlugin

#endif
