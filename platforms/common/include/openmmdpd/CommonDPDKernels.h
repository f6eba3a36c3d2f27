#ifndef OPENMMDPD_COMMONDPDKERNELS_H_
#define OPENMMDPD_COMMONDPDKERNELS_H_

#include "openmmdpd/CommonCellList.h"
#include "openmmdpd/CommonDPDVVDynamics.h"
#include "openmmdpd/CommonDenOtterClarkeDynamics.h"
#include "openmmdpd/CommonEDPDDynamics.h"
#include "openmmdpd/CommonStaggeredDynamics.h"
#include "openmmdpd/CommonSweepDynamics.h"
#include "openmmdpd/DPDKernels.h"
#include "openmmdpd/DynamicsStepKernel.h"
#include "openmm/common/ComputeContext.h"
#include "openmm/common/ContextSelector.h"
#include <memory>

namespace DPDPlugin {

/**
 * An integrator's step kernel on a ComputeContext (OpenCL, CUDA), its update rule in
 * Dynamics; what CommonDynamics::refuseUnsupported names raises an OpenMMException naming the
 * platform before anything changes.
 */
template <class Interface, class Integrator, class Dynamics>
class CommonStepKernel : public DynamicsStepKernel<Interface, Integrator, Dynamics> {
public:
    CommonStepKernel(std::string name, const OpenMM::Platform& platform, OpenMM::ComputeContext& cc) :
            DynamicsStepKernel<Interface, Integrator, Dynamics>(name, platform), cc(cc) {}
    void initialize(const OpenMM::System& system, const Integrator& integrator) override {
        CommonDynamics::refuseUnsupported(system, integrator, this->getPlatform().getName());
        // The integrator's kernel finishes the platform's set-up (OpenMM's own integrators do
        // the same): until then the Context has no particle arrays.
        cc.initializeContexts();
        OpenMM::ContextSelector selector(cc);
        DynamicsStepKernel<Interface, Integrator, Dynamics>::initialize(system, integrator);
    }
    void execute(OpenMM::ContextImpl& context, const Integrator& integrator) override {
        CommonDynamics::refuseUnsupported(context.getSystem(), integrator, this->getPlatform().getName());
        DynamicsStepKernel<Interface, Integrator, Dynamics>::execute(context, integrator);
    }

protected:
    Dynamics* createDynamics(const OpenMM::System& system, const Integrator& integrator) override {
        return new Dynamics(cc, system, integrator, this->getPlatform().getName());
    }

private:
    OpenMM::ComputeContext& cc;
};

using CommonIntegrateDPDVVStepKernel = CommonStepKernel<IntegrateDPDVVStepKernel, DPDVVIntegrator, CommonDPDVVDynamics>;
using CommonIntegrateShardlowStepKernel = CommonStepKernel<IntegrateShardlowStepKernel, ShardlowIntegrator, CommonShardlowDynamics>;
using CommonIntegrateLoweAndersenStepKernel =
        CommonStepKernel<IntegrateLoweAndersenStepKernel, LoweAndersenIntegrator, CommonLoweAndersenDynamics>;

using CommonIntegrateStaggeredDPDStepKernel =
        CommonStepKernel<IntegrateStaggeredDPDStepKernel, StaggeredDPDIntegrator, CommonStaggeredDynamics>;
using CommonIntegrateDenOtterClarkeStepKernel =
        MeasuringStepKernel<CommonStepKernel<IntegrateDenOtterClarkeStepKernel, DenOtterClarkeIntegrator, CommonDenOtterClarkeDynamics>>;

class CommonIntegrateEDPDStepKernel : public CommonStepKernel<IntegrateEDPDStepKernel, EDPDIntegrator, CommonEDPDDynamics> {
public:
    using CommonStepKernel::CommonStepKernel;
    bool getPairVariable(int i, int j, double& value, long long& step) const override {
        return this->dynamics->getPairVariable(i, j, value, step);
    }
    long long getNumPairVariables() const override { return this->dynamics->getNumPairVariables(); }
};

/** DPDSoftRepulsionForce on a ComputeContext: a gather over a cell list, forces in fixed point (kernels/softRepulsion.cc). */
class CommonSoftRepulsionKernel : public CalcDPDSoftRepulsionForceKernel {
public:
    CommonSoftRepulsionKernel(std::string name, const OpenMM::Platform& platform, OpenMM::ComputeContext& cc) :
            CalcDPDSoftRepulsionForceKernel(name, platform), cc(cc) {}
    void initialize(const OpenMM::System& system, const DPDSoftRepulsionForce& force) override;
    double execute(OpenMM::ContextImpl& context, bool includeForces, bool includeEnergy) override;
    void copyParametersToContext(OpenMM::ContextImpl& context, const DPDSoftRepulsionForce& force) override;
    /** The exact pair virial at the current positions: the same pairs, each thread's sum downloaded and added in double. */
    std::array<double, 6> computeVirial(OpenMM::ContextImpl& context) override;

private:
    void setParameters(const DPDSoftRepulsionForce& force);
    void uploadExclusions(const DPDSoftRepulsionForce& force);
    /** Run the kernel on as many threads as OpenMM's energy buffer has slots (virialOnly: see kernels/softRepulsion.cc). */
    int run(bool virialOnly);
    OpenMM::ComputeContext& cc;
    std::unique_ptr<CommonCellList> cells;
    OpenMM::ComputeKernel kernel;
    OpenMM::ComputeArray atomType, typeParams, exclusionStart, exclusions, virialRows;
    double maxCutoff = 0;
    int numTypes = 0;
};

} // namespace DPDPlugin

#endif
