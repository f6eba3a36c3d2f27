#ifndef OPENMMDPD_COMMONPOSITIONSTRAIN_H_
#define OPENMMDPD_COMMONPOSITIONSTRAIN_H_

#include "openmmdpd/PressureTensor.h"
#include "openmm/common/ComputeContext.h"
#include "openmm/common/ComputeArray.h"

namespace DPDPlugin {

/** PositionStrain on a ComputeContext: OpenMM's posq (and its mixed-precision correction), kept by atom (kernels/positionStrain.cc). */
class CommonPositionStrain : public PositionStrain {
public:
    /** @param program  a program compiled with kernels/positionStrain.cc */
    CommonPositionStrain(OpenMM::ComputeContext& cc, OpenMM::ComputeProgram program);
    void strain(OpenMM::ContextImpl& context, int a, int b, double strain) override;
    void restore(OpenMM::ContextImpl& context) override;
    /** On the ComputeContext itself (OpenMM's kernels take the box it holds). */
    void setBox(OpenMM::ContextImpl& context, const OpenMM::Vec3* box) override;

private:
    OpenMM::ComputeContext& cc;
    OpenMM::ComputeKernel saveKernel, strainKernel, restoreKernel;
    OpenMM::ComputeArray savedPosq, savedCorrection;
    bool saved = false;
};

} // namespace DPDPlugin

#endif
