#ifndef OPENMMDPD_REFERENCESTAGGEREDDYNAMICS_H_
#define OPENMMDPD_REFERENCESTAGGEREDDYNAMICS_H_

#include "openmmdpd/ReferenceDynamics.h"
#include "openmmdpd/StaggeredDPDIntegrator.h"
#include "openmm/OpenMMException.h"

namespace DPDPlugin {

// PLACEHOLDER (to be written)
class ReferenceStaggeredDynamics : public ReferenceDynamics {
public:
    ReferenceStaggeredDynamics(const OpenMM::System& system, const StaggeredDPDIntegrator& integrator) : ReferenceDynamics(system, integrator, 1) {}
    void step(OpenMM::ContextImpl&, const StaggeredDPDIntegrator&) { throw OpenMM::OpenMMException("not yet on Reference"); }
};

} // namespace DPDPlugin

#endif
