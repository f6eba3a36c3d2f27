#ifndef OPENMMDPD_REFERENCEDPDKERNELS_H_
#define OPENMMDPD_REFERENCEDPDKERNELS_H_

#include "openmmdpd/DynamicsStepKernel.h"
#include "openmmdpd/ReferenceDPDVVDynamics.h"
#include "openmmdpd/ReferenceDenOtterClarkeDynamics.h"
#include "openmmdpd/ReferenceEDPDDynamics.h"
#include "openmmdpd/ReferenceStaggeredDynamics.h"
#include "openmmdpd/ReferenceSweepDynamics.h"

namespace DPDPlugin {

/** A Reference step kernel: a ReferenceDynamics subclass, in the calling thread. */
template <class Interface, class Integrator, class Dynamics>
class ReferenceStepKernel : public DynamicsStepKernel<Interface, Integrator, Dynamics> {
public:
    using DynamicsStepKernel<Interface, Integrator, Dynamics>::DynamicsStepKernel;

protected:
    Dynamics* createDynamics(const OpenMM::System& system, const Integrator& integrator) override {
        return new Dynamics(system, integrator);
    }
};

using ReferenceIntegrateDPDVVStepKernel = ReferenceStepKernel<IntegrateDPDVVStepKernel, DPDVVIntegrator, ReferenceDPDVVDynamics>;
using ReferenceIntegrateShardlowStepKernel =
        ReferenceStepKernel<IntegrateShardlowStepKernel, ShardlowIntegrator, ReferenceShardlowDynamics>;
using ReferenceIntegrateLoweAndersenStepKernel =
        ReferenceStepKernel<IntegrateLoweAndersenStepKernel, LoweAndersenIntegrator, ReferenceLoweAndersenDynamics>;
using ReferenceIntegrateStaggeredDPDStepKernel =
        ReferenceStepKernel<IntegrateStaggeredDPDStepKernel, StaggeredDPDIntegrator, ReferenceStaggeredDynamics>;

using ReferenceIntegrateDenOtterClarkeStepKernel =
        MeasuringStepKernel<ReferenceStepKernel<IntegrateDenOtterClarkeStepKernel, DenOtterClarkeIntegrator, ReferenceDenOtterClarkeDynamics>>;

class ReferenceIntegrateEDPDStepKernel : public ReferenceStepKernel<IntegrateEDPDStepKernel, EDPDIntegrator, ReferenceEDPDDynamics> {
public:
    using ReferenceStepKernel::ReferenceStepKernel;
    bool getPairVariable(int i, int j, double& value, long long& step) const override {
        return this->dynamics->getPairVariable(i, j, value, step);
    }
    long long getNumPairVariables() const override { return this->dynamics->getNumPairVariables(); }
};

} // namespace DPDPlugin

#endif
