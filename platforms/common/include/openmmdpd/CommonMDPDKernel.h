#ifndef OPENMMDPD_COMMONMDPDKERNEL_H_
#define OPENMMDPD_COMMONMDPDKERNEL_H_

#include "openmmdpd/CommonCellList.h"
#include "openmmdpd/DPDKernels.h"
#include "openmm/common/ComputeContext.h"
#include <memory>

namespace DPDPlugin {

/** MDPDForce on a ComputeContext: two gathers over a cell list, the densities then the forces in fixed point (kernels/mdpd.cc). */
class CommonMDPDKernel : public CalcMDPDForceKernel {
public:
    CommonMDPDKernel(std::string name, const OpenMM::Platform& platform, OpenMM::ComputeContext& cc) : CalcMDPDForceKernel(name, platform), cc(cc) {}
    void initialize(const OpenMM::System& system, const MDPDForce& force) override;
    double execute(OpenMM::ContextImpl& context, bool includeForces, bool includeEnergy) override;
    void copyParametersToContext(OpenMM::ContextImpl& context, const MDPDForce& force) override;
    /** The exact pair virial at the current positions: each thread's sum downloaded and added in double. */
    std::array<double, 6> computeVirial(OpenMM::ContextImpl& context) override;

private:
    void setParameters(const MDPDForce& force);
    void createKernels(OpenMM::ComputeProgram& program);
    /** Run both kernels, the second on as many threads as OpenMM's energy buffer has slots; returns that number. */
    int run(bool virialOnly);
    OpenMM::ComputeContext& cc;
    std::unique_ptr<CommonCellList> cells;
    OpenMM::ComputeKernel densityKernel, forceKernel;
    OpenMM::ComputeArray atomType, typeParams, typeB, exclusionStart, exclusions, density, virialRows;
    double maxCutoff = 0, densityParams[4] = {0, 0, 0, 0};
    int numTypes = 0;
};

} // namespace DPDPlugin

#endif
