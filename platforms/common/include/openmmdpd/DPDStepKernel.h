#ifndef OPENMMDPD_DPDSTEPKERNEL_H_
#define OPENMMDPD_DPDSTEPKERNEL_H_

#include "openmmdpd/DPDKernels.h"
#include "openmmdpd/PairDynamics.h"
#include <memory>

namespace DPDPlugin {

/**
 * The step kernel of every DPD integrator on every platform: the integrator's update rule
 * (a PairDynamics) run on the executor the platform supplies (serial on Reference,
 * OpenMM's ThreadPool on CPU).
 */
class DPDStepKernel : public IntegrateDPDStepKernel {
public:
    DPDStepKernel(std::string name, const OpenMM::Platform& platform, std::unique_ptr<ParallelExecutor> executor) :
            IntegrateDPDStepKernel(name, platform), executor(std::move(executor)) {}
    void initialize(const OpenMM::System& system, const DPDThermostatIntegrator& integrator) override;
    void execute(OpenMM::ContextImpl& context, const DPDThermostatIntegrator& integrator) override { dynamics->step(context, integrator); }
    double computeKineticEnergy(OpenMM::ContextImpl& context) override { return dynamics->computeKineticEnergy(context); }
    void invalidateForces() override { dynamics->invalidateForces(); }
    void createCheckpoint(OpenMM::ContextImpl& context, std::ostream& stream) const override { dynamics->createCheckpoint(stream); }
    void loadCheckpoint(OpenMM::ContextImpl& context, std::istream& stream) override { dynamics->loadCheckpoint(context, stream); }
    /** The kernel names a platform registers DPDStepKernel under. */
    static std::vector<std::string> names() {
        return {DPDVVName(), ShardlowName(), LoweAndersenName(), StaggeredName()};
    }

private:
    std::unique_ptr<ParallelExecutor> executor;
    std::unique_ptr<PairDynamics> dynamics;
};

} // namespace DPDPlugin

#endif
