#ifndef OPENMMDPD_OPENCLDPDKERNELFACTORY_H_
#define OPENMMDPD_OPENCLDPDKERNELFACTORY_H_

#include "openmm/common/ComputeContext.h"
#include "openmm/internal/ContextImpl.h"
#include "openmm/internal/windowsExport.h"

namespace DPDPlugin {

/** The ComputeContext of a Context on the OpenCL platform (the common kernels run on it; the tests reach it here). */
OPENMM_EXPORT OpenMM::ComputeContext& getOpenCLComputeContext(OpenMM::ContextImpl& context);

} // namespace DPDPlugin

#endif
