#ifndef OPENMMDPD_COMMONDENOTTERCLARKEDYNAMICS_H_
#define OPENMMDPD_COMMONDENOTTERCLARKEDYNAMICS_H_

#include "openmmdpd/CommonDynamics.h"
#include "openmmdpd/DenOtterClarkeIntegrator.h"
#include "openmmdpd/DenOtterClarkeSums.h"

namespace DPDPlugin {

/**
 * den Otter and Clarke's leap-frog on the device, step for step as
 * ReferenceDenOtterClarkeDynamics (kernels/denOtterClarke.cc): nothing is carried; each
 * step evaluates FC, FD and FR at its start, adds its measured terms to the sums, and moves
 * with the integrator's prefactors, constraints included.
 */
class CommonDenOtterClarkeDynamics : public CommonDynamics {
public:
    CommonDenOtterClarkeDynamics(OpenMM::ComputeContext& cc, const OpenMM::System& system, const DenOtterClarkeIntegrator& integrator,
                                 const std::string& platform);
    void step(OpenMM::ContextImpl& context, const DenOtterClarkeIntegrator& integrator);
    const DenOtterClarkeSums& getSums() const { return sums; }

private:
    /** sums += this step's terms, each work item's sums added on the host in double. */
    void measure(double dt);
    OpenMM::ComputeKernel termsKernel, stepKernel;
    OpenMM::ComputeArray termRows;
    int termThreads;
    long long activeAtoms = 0;  // the particles with mass: the terms each step adds
    double thermostatMass;
    DenOtterClarkeSums sums;
};

} // namespace DPDPlugin

#endif
