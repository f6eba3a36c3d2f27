#ifndef OPENMMDPD_REFERENCEDPDKERNELS_H_
#define OPENMMDPD_REFERENCEDPDKERNELS_H_

#include "openmmdpd/DPDKernels.h"
#include "openmmdpd/DPDVVDynamics.h"
#include <memory>

namespace DPDPlugin {

/** The Reference platform's DPD-VV step: the common update rule run serially. */
class ReferenceIntegrateDPDVVStepKernel : public IntegrateDPDVVStepKernel {
public:
    ReferenceIntegrateDPDVVStepKernel(std::string name, const OpenMM::Platform& platform) : IntegrateDPDVVStepKernel(name, platform) {}
    void initialize(const OpenMM::System& system, const DPDVVIntegrator& integrator) override {
        dynamics.reset(new DPDVVDynamics(system, integrator, executor, DEFAULT_PAIR_SKIN));
    }
    void execute(OpenMM::ContextImpl& context, const DPDVVIntegrator& integrator) override { dynamics->step(context, integrator); }
    double computeKineticEnergy(OpenMM::ContextImpl& context, const DPDVVIntegrator& integrator) override {
        return dynamics->computeKineticEnergy(context);
    }
    void invalidateForces() override { dynamics->invalidateForces(); }
    void createCheckpoint(OpenMM::ContextImpl& context, std::ostream& stream) const override { dynamics->createCheckpoint(stream); }
    void loadCheckpoint(OpenMM::ContextImpl& context, std::istream& stream) override { dynamics->loadCheckpoint(context, stream); }

private:
    SerialExecutor executor;
    std::unique_ptr<DPDVVDynamics> dynamics;
};

} // namespace DPDPlugin

#endif
