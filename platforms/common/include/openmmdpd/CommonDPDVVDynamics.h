#ifndef OPENMMDPD_COMMONDPDVVDYNAMICS_H_
#define OPENMMDPD_COMMONDPDVVDYNAMICS_H_

#include "openmmdpd/CommonDynamics.h"
#include "openmmdpd/DPDVVIntegrator.h"

namespace DPDPlugin {

/**
 * Groot-Warren (lambda) and DPD-VV on the device, step for step as ReferenceDPDVVDynamics
 * (kernels/dpdvv.cc).  The carried force is FC + FD + FR of the last evaluation.
 */
class CommonDPDVVDynamics : public CommonDynamics {
public:
    CommonDPDVVDynamics(OpenMM::ComputeContext& cc, const OpenMM::System& system, const DPDVVIntegrator& integrator,
                        const std::string& platform);
    void step(OpenMM::ContextImpl& context, const DPDVVIntegrator& integrator);

private:
    void grootWarrenStep(OpenMM::ContextImpl& context, const DPDVVIntegrator& integrator, long long next);
    void dpdvvStep(OpenMM::ContextImpl& context, const DPDVVIntegrator& integrator, long long next);
    OpenMM::ComputeKernel grootWarren1, grootWarren2, dpdvv1, dpdvv2, dpdvv3;
};

} // namespace DPDPlugin

#endif
