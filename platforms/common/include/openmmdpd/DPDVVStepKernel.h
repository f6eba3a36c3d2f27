#ifndef OPENMMDPD_DPDVVSTEPKERNEL_H_
#define OPENMMDPD_DPDVVSTEPKERNEL_H_

#include "openmmdpd/DPDKernels.h"
#include "openmmdpd/DPDVVDynamics.h"
#include <memory>

namespace DPDPlugin {

/**
 * The DPD-VV step kernel of every platform: the common update rule run on the executor the
 * platform supplies (serial on Reference, OpenMM's ThreadPool on CPU).
 */
class DPDVVStepKernel : public IntegrateDPDVVStepKernel {
public:
    DPDVVStepKernel(std::string name, const OpenMM::Platform& platform, std::unique_ptr<ParallelExecutor> executor) :
            IntegrateDPDVVStepKernel(name, platform), executor(std::move(executor)) {}
    void initialize(const OpenMM::System& system, const DPDVVIntegrator& integrator) override {
        dynamics.reset(new DPDVVDynamics(system, integrator, *executor));
    }
    void execute(OpenMM::ContextImpl& context, const DPDVVIntegrator& integrator) override { dynamics->step(context, integrator); }
    double computeKineticEnergy(OpenMM::ContextImpl& context, const DPDVVIntegrator& integrator) override {
        return dynamics->computeKineticEnergy(context);
    }
    void invalidateForces() override { dynamics->invalidateForces(); }
    void createCheckpoint(OpenMM::ContextImpl& context, std::ostream& stream) const override { dynamics->createCheckpoint(stream); }
    void loadCheckpoint(OpenMM::ContextImpl& context, std::istream& stream) override { dynamics->loadCheckpoint(context, stream); }

private:
    std::unique_ptr<ParallelExecutor> executor;
    std::unique_ptr<DPDVVDynamics> dynamics;
};

} // namespace DPDPlugin

#endif
