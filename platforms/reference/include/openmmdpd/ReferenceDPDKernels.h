#ifndef OPENMMDPD_REFERENCEDPDKERNELS_H_
#define OPENMMDPD_REFERENCEDPDKERNELS_H_

#include "openmmdpd/DPDKernels.h"
#include "openmmdpd/ReferenceDPDVVDynamics.h"
#include "openmmdpd/ReferenceEDPDDynamics.h"
#include "openmmdpd/ReferenceStaggeredDynamics.h"
#include "openmmdpd/ReferenceSweepDynamics.h"
#include <memory>

namespace DPDPlugin {

/** A Reference step kernel: the typed interface Interface of Integrator, run by a ReferenceDynamics. */
template <class Interface, class Integrator, class Dynamics>
class ReferenceStepKernel : public Interface {
public:
    ReferenceStepKernel(std::string name, const OpenMM::Platform& platform) : Interface(name, platform) {}
    void initialize(const OpenMM::System& system, const Integrator& integrator) override {
        dynamics.reset(new Dynamics(system, integrator));
        parametersVersion = integrator.getThermostatParametersVersion();
    }
    void execute(OpenMM::ContextImpl& context, const Integrator& integrator) override {
        if (integrator.getThermostatParametersVersion() != parametersVersion) {
            dynamics->updateParameters(context.getSystem(), integrator);
            parametersVersion = integrator.getThermostatParametersVersion();
        }
        dynamics->step(context, integrator);
    }
    double computeKineticEnergy(OpenMM::ContextImpl& context) override { return dynamics->computeKineticEnergy(context); }
    void invalidateForces() override { dynamics->invalidateForces(); }
    void createCheckpoint(OpenMM::ContextImpl&, std::ostream& stream) const override { dynamics->createCheckpoint(stream); }
    void loadCheckpoint(OpenMM::ContextImpl& context, std::istream& stream) override { dynamics->loadCheckpoint(context, stream); }

protected:
    std::unique_ptr<Dynamics> dynamics;
    int parametersVersion = 0;
};

using ReferenceIntegrateDPDVVStepKernel = ReferenceStepKernel<IntegrateDPDVVStepKernel, DPDVVIntegrator, ReferenceDPDVVDynamics>;
using ReferenceIntegrateShardlowStepKernel =
        ReferenceStepKernel<IntegrateShardlowStepKernel, ShardlowIntegrator, ReferenceShardlowDynamics>;
using ReferenceIntegrateLoweAndersenStepKernel =
        ReferenceStepKernel<IntegrateLoweAndersenStepKernel, LoweAndersenIntegrator, ReferenceLoweAndersenDynamics>;
using ReferenceIntegrateStaggeredDPDStepKernel =
        ReferenceStepKernel<IntegrateStaggeredDPDStepKernel, StaggeredDPDIntegrator, ReferenceStaggeredDynamics>;

class ReferenceIntegrateEDPDStepKernel : public ReferenceStepKernel<IntegrateEDPDStepKernel, EDPDIntegrator, ReferenceEDPDDynamics> {
public:
    using ReferenceStepKernel::ReferenceStepKernel;
    bool getPairVariable(int i, int j, double& value, long long& step) const override {
        return dynamics->getPairVariable(i, j, value, step);
    }
    long long getNumPairVariables() const override { return dynamics->getNumPairVariables(); }
};

} // namespace DPDPlugin

#endif
