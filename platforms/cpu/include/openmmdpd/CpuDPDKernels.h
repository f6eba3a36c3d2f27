#ifndef OPENMMDPD_CPUDPDKERNELS_H_
#define OPENMMDPD_CPUDPDKERNELS_H_

#include "openmmdpd/DPDKernels.h"
#include "openmmdpd/DPDVVDynamics.h"
#include "openmmdpd/EDPDDynamics.h"
#include "openmmdpd/StaggeredDynamics.h"
#include "openmmdpd/SweepDynamics.h"
#include "openmmdpd/ThreadPoolExecutor.h"
#include <memory>

namespace DPDPlugin {

/**
 * A CPU step kernel: the typed interface Interface of Integrator, implemented by a
 * Dynamics (a PairDynamics subclass) running on the CPU platform's ThreadPool.
 */
template <class Interface, class Integrator, class Dynamics>
class CpuStepKernel : public Interface {
public:
    CpuStepKernel(std::string name, const OpenMM::Platform& platform, OpenMM::ThreadPool& threads) :
            Interface(name, platform), executor(threads) {}
    void initialize(const OpenMM::System& system, const Integrator& integrator) override {
        dynamics.reset(new Dynamics(system, integrator, executor));
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
    ThreadPoolExecutor executor;
    std::unique_ptr<Dynamics> dynamics;
    int parametersVersion = 0;
};

using CpuIntegrateDPDVVStepKernel = CpuStepKernel<IntegrateDPDVVStepKernel, DPDVVIntegrator, DPDVVDynamics>;
using CpuIntegrateShardlowStepKernel = CpuStepKernel<IntegrateShardlowStepKernel, ShardlowIntegrator, ShardlowDynamics>;
using CpuIntegrateLoweAndersenStepKernel = CpuStepKernel<IntegrateLoweAndersenStepKernel, LoweAndersenIntegrator, LoweAndersenDynamics>;
using CpuIntegrateStaggeredDPDStepKernel =
        CpuStepKernel<IntegrateStaggeredDPDStepKernel, StaggeredDPDIntegrator, StaggeredDynamics>;

class CpuIntegrateEDPDStepKernel : public CpuStepKernel<IntegrateEDPDStepKernel, EDPDIntegrator, EDPDDynamics> {
public:
    using CpuStepKernel::CpuStepKernel;
    bool getPairVariable(int i, int j, double& value, long long& step) const override {
        return dynamics->getMemory().find(i, j, value, step);
    }
    long long getNumPairVariables() const override { return dynamics->getMemory().size(); }
};

} // namespace DPDPlugin

#endif
