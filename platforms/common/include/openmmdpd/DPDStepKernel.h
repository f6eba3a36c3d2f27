#ifndef OPENMMDPD_DPDSTEPKERNEL_H_
#define OPENMMDPD_DPDSTEPKERNEL_H_

#include "openmmdpd/DPDKernels.h"
#include "openmmdpd/PairDynamics.h"
#include <functional>
#include <memory>

namespace DPDPlugin {

/**
 * A step kernel that runs an integrator's update rule (a PairDynamics) on the executor the
 * platform supplies (serial on Reference, OpenMM's ThreadPool on CPU).  Interface is the
 * kernel interface it implements.
 */
template <class Interface>
class PairDynamicsKernel : public Interface {
public:
    PairDynamicsKernel(std::string name, const OpenMM::Platform& platform, std::unique_ptr<ParallelExecutor> executor) :
            Interface(name, platform), executor(std::move(executor)) {}
    void execute(OpenMM::ContextImpl& context, const DPDThermostatIntegrator& integrator) override { dynamics->step(context, integrator); }
    double computeKineticEnergy(OpenMM::ContextImpl& context) override { return dynamics->computeKineticEnergy(context); }
    void invalidateForces() override { dynamics->invalidateForces(); }
    void createCheckpoint(OpenMM::ContextImpl& context, std::ostream& stream) const override { dynamics->createCheckpoint(stream); }
    void loadCheckpoint(OpenMM::ContextImpl& context, std::istream& stream) override { dynamics->loadCheckpoint(context, stream); }

protected:
    std::unique_ptr<ParallelExecutor> executor;
    std::unique_ptr<PairDynamics> dynamics;
};

/** The step kernel of DPDVVIntegrator, ShardlowIntegrator, LoweAndersenIntegrator and StaggeredDPDIntegrator. */
class DPDStepKernel : public PairDynamicsKernel<IntegrateDPDStepKernel> {
public:
    using PairDynamicsKernel::PairDynamicsKernel;
    void initialize(const OpenMM::System& system, const DPDThermostatIntegrator& integrator) override;
    /** The kernel names a platform registers DPDStepKernel under. */
    static std::vector<std::string> names() {
        return {DPDVVName(), ShardlowName(), LoweAndersenName(), StaggeredName()};
    }
};

/** The step kernel of EDPDIntegrator. */
class EDPDStepKernel : public PairDynamicsKernel<IntegrateEDPDStepKernel> {
public:
    using PairDynamicsKernel::PairDynamicsKernel;
    void initialize(const OpenMM::System& system, const DPDThermostatIntegrator& integrator) override;
    bool getPairVariable(int i, int j, double& value, long long& step) const override;
    long long getNumPairVariables() const override;
};

/** Every kernel name this plugin implements, on every platform. */
std::vector<std::string> dpdKernelNames();

/**
 * The kernel implementing `name` (one of dpdKernelNames()), running on executors from
 * makeExecutor; nullptr for a name this plugin does not know.
 */
OpenMM::KernelImpl* createDPDKernel(const std::string& name, const OpenMM::Platform& platform,
                                    const std::function<std::unique_ptr<ParallelExecutor>()>& makeExecutor);

} // namespace DPDPlugin

#endif
