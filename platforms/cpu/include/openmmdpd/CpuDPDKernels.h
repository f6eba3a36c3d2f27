#ifndef OPENMMDPD_CPUDPDKERNELS_H_
#define OPENMMDPD_CPUDPDKERNELS_H_

#include "openmmdpd/DynamicsStepKernel.h"
#include "openmmdpd/DPDVVDynamics.h"
#include "openmmdpd/DenOtterClarkeDynamics.h"
#include "openmmdpd/EDPDDynamics.h"
#include "openmmdpd/StaggeredDynamics.h"
#include "openmmdpd/SweepDynamics.h"
#include "openmmdpd/ThreadPoolExecutor.h"

namespace DPDPlugin {

/** A CPU step kernel: a Dynamics (a PairDynamics subclass) on the CPU platform's ThreadPool. */
template <class Interface, class Integrator, class Dynamics>
class CpuStepKernel : public DynamicsStepKernel<Interface, Integrator, Dynamics> {
public:
    CpuStepKernel(std::string name, const OpenMM::Platform& platform, OpenMM::ThreadPool& threads) :
            DynamicsStepKernel<Interface, Integrator, Dynamics>(name, platform), executor(threads) {}

protected:
    Dynamics* createDynamics(const OpenMM::System& system, const Integrator& integrator) override {
        return new Dynamics(system, integrator, executor);
    }
    ThreadPoolExecutor executor;
};

using CpuIntegrateDPDVVStepKernel = CpuStepKernel<IntegrateDPDVVStepKernel, DPDVVIntegrator, DPDVVDynamics>;
using CpuIntegrateShardlowStepKernel = CpuStepKernel<IntegrateShardlowStepKernel, ShardlowIntegrator, ShardlowDynamics>;
using CpuIntegrateLoweAndersenStepKernel = CpuStepKernel<IntegrateLoweAndersenStepKernel, LoweAndersenIntegrator, LoweAndersenDynamics>;
using CpuIntegrateStaggeredDPDStepKernel =
        CpuStepKernel<IntegrateStaggeredDPDStepKernel, StaggeredDPDIntegrator, StaggeredDynamics>;

using CpuIntegrateDenOtterClarkeStepKernel =
        MeasuringStepKernel<CpuStepKernel<IntegrateDenOtterClarkeStepKernel, DenOtterClarkeIntegrator, DenOtterClarkeDynamics>>;

class CpuIntegrateEDPDStepKernel : public CpuStepKernel<IntegrateEDPDStepKernel, EDPDIntegrator, EDPDDynamics> {
public:
    using CpuStepKernel::CpuStepKernel;
    bool getPairVariable(int i, int j, double& value, long long& step) const override {
        return this->dynamics->getMemory().find(i, j, value, step);
    }
    long long getNumPairVariables() const override { return this->dynamics->getMemory().size(); }
};

} // namespace DPDPlugin

#endif
