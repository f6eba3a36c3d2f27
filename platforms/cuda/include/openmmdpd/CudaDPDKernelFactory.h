#ifndef OPENMMDPD_CUDADPDKERNELFACTORY_H_
#define OPENMMDPD_CUDADPDKERNELFACTORY_H_

#include "openmm/common/ComputeContext.h"
#include "openmm/internal/ContextImpl.h"
#include "openmm/internal/windowsExport.h"

namespace DPDPlugin {

/** The ComputeContext of a Context on the CUDA platform (the common kernels run on it; the tests reach it here). */
OPENMM_EXPORT OpenMM::ComputeContext& getCudaComputeContext(OpenMM::ContextImpl& context);

} // namespace DPDPlugin

#endif
