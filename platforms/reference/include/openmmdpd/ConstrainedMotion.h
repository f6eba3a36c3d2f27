#ifndef OPENMMDPD_CONSTRAINEDMOTION_H_
#define OPENMMDPD_CONSTRAINEDMOTION_H_

#include "openmm/Vec3.h"
#include "openmm/internal/ContextImpl.h"
#include <vector>

namespace DPDPlugin {

/**
 * Constraints and virtual sites, applied as OpenMM's own Verlet-type integrators apply them,
 * for every update rule of every platform that keeps its state in the Reference platform's
 * data (Reference and CPU).  After a drift: the new positions are constrained against the old
 * ones (SHAKE/CCMA/SETTLE from the platform's ReferenceConstraints), the velocities take the
 * correction (r_constrained - r_unconstrained)/dt, so that the drift part of v is
 * (r_constrained - r_old)/dt, and the virtual sites are placed from their parents.  After a
 * velocity change: the velocity components along the constraints are removed (RATTLE).
 * The tolerance is the integrator's getConstraintTolerance().  With neither constraints nor
 * virtual sites every call returns at once.
 */
class ConstrainedMotion {
public:
    explicit ConstrainedMotion(const OpenMM::System& system);
    bool hasConstraints() const { return constraints; }
    /** Call before a drift moves the positions (keeps them as the reference of the constraints). */
    void startDrift(const std::vector<OpenMM::Vec3>& positions);
    /**
     * Call after the drift of a step of length dt: constrain the positions, correct the
     * Context's velocities (and `alsoCorrect`, e.g. predicted velocities, if given) by the
     * constraint displacement over dt, place the virtual sites.
     */
    void finishDrift(OpenMM::ContextImpl& context, double dt, std::vector<OpenMM::Vec3>* alsoCorrect = nullptr);
    /** Remove the Context's velocity components along the constraints. */
    void constrainVelocities(OpenMM::ContextImpl& context);

private:
    std::vector<double> inverseMasses;  // not const: ReferenceConstraints takes it by reference
    std::vector<OpenMM::Vec3> oldPositions, unconstrained;
    bool constraints, sites;
};

} // namespace DPDPlugin

#endif
