#ifndef OPENMMDPD_DENOTTERCLARKEDYNAMICS_H_
#define OPENMMDPD_DENOTTERCLARKEDYNAMICS_H_

#include "openmmdpd/DenOtterClarkeIntegrator.h"
#include "openmmdpd/DenOtterClarkeSums.h"
#include "openmmdpd/PairDynamics.h"

namespace DPDPlugin {

/**
 * den Otter and Clarke's leap-frog (docs/theory/den-otter-clarke.md).  As on the Reference
 * platform, nothing is carried: the forces of Table II's step (3) are evaluated at the
 * start of the next step.
 */
class DenOtterClarkeDynamics : public PairDynamics {
public:
    DenOtterClarkeDynamics(const OpenMM::System& system, const DenOtterClarkeIntegrator& integrator, ParallelExecutor& executor);
    void step(OpenMM::ContextImpl& context, const DenOtterClarkeIntegrator& integrator);
    const DenOtterClarkeSums& getSums() const { return sums; }

private:
    /** sums += this step's terms, per worker, added in worker order. */
    void measure(const std::vector<OpenMM::Vec3>& velocities, double dt);
    std::vector<OpenMM::Vec3> dissipative, random;
    DenOtterClarkeSums sums;
    std::vector<DenOtterClarkeSums> workerTerms;
};

} // namespace DPDPlugin

#endif
