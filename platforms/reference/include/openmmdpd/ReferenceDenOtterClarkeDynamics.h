#ifndef OPENMMDPD_REFERENCEDENOTTERCLARKEDYNAMICS_H_
#define OPENMMDPD_REFERENCEDENOTTERCLARKEDYNAMICS_H_

#include "openmmdpd/DenOtterClarkeIntegrator.h"
#include "openmmdpd/DenOtterClarkeSums.h"
#include "openmmdpd/ReferenceDynamics.h"

namespace DPDPlugin {

/**
 * den Otter and Clarke's leap-frog (docs/theory/den-otter-clarke.md).  Nothing is carried from one
 * step to the next: the forces of Table II's step (3) are evaluated at the start of the
 * next step instead, from the same positions, velocities and random numbers.
 */
class ReferenceDenOtterClarkeDynamics : public ReferenceDynamics {
public:
    ReferenceDenOtterClarkeDynamics(const OpenMM::System& system, const DenOtterClarkeIntegrator& integrator) :
            ReferenceDynamics(system, integrator, 1) {}
    void step(OpenMM::ContextImpl& context, const DenOtterClarkeIntegrator& integrator);
    const DenOtterClarkeSums& getSums() const { return sums; }

private:
    DenOtterClarkeSums sums;
};

} // namespace DPDPlugin

#endif
