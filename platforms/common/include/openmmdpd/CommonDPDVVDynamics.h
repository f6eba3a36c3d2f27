#ifndef OPENMMDPD_COMMONDPDVVDYNAMICS_H_
#define OPENMMDPD_COMMONDPDVVDYNAMICS_H_

#include "openmmdpd/CommonDynamics.h"
#include "openmmdpd/DPDVVIntegrator.h"

namespace DPDPlugin {

/**
 * Groot-Warren (lambda), DPD-VV and SC-VV on the device, step for step as
 * ReferenceDPDVVDynamics (kernels/dpdvv.cc), constraints included.  The carried force is FC + FD + FR of the last
 * evaluation.
 */
class CommonDPDVVDynamics : public CommonDynamics {
public:
    CommonDPDVVDynamics(OpenMM::ComputeContext& cc, const OpenMM::System& system, const DPDVVIntegrator& integrator,
                        const std::string& platform);
    void step(OpenMM::ContextImpl& context, const DPDVVIntegrator& integrator);

private:
    void grootWarrenStep(OpenMM::ContextImpl& context, const DPDVVIntegrator& integrator, long long next);
    void dpdvvStep(OpenMM::ContextImpl& context, const DPDVVIntegrator& integrator, long long next);
    /** DPD-VV's (4b) and (5), repeated by SC-VV until the kinetic energy settles (as the Reference's). */
    void dissipativeIterations(const DPDVVIntegrator& integrator, long long next);
    OpenMM::ComputeKernel grootWarren1, grootWarren2, dpdvv1, dpdvv2, dissipativeKick, dpdvv3;
    OpenMM::ComputeArray noDissipative;  // by atom: the velocities of DPD-VV's (4a)
};

} // namespace DPDPlugin

#endif
