#ifndef OPENMMDPD_REFERENCEEDPDDYNAMICS_H_
#define OPENMMDPD_REFERENCEEDPDDYNAMICS_H_

#include "openmmdpd/EDPDIntegrator.h"
#include "openmmdpd/ReferenceDynamics.h"
#include "openmm/OpenMMException.h"

namespace DPDPlugin {

// PLACEHOLDER (to be written)
class ReferenceEDPDDynamics : public ReferenceDynamics {
public:
    ReferenceEDPDDynamics(const OpenMM::System& system, const EDPDIntegrator& integrator) : ReferenceDynamics(system, integrator, 1) {}
    void step(OpenMM::ContextImpl&, const EDPDIntegrator&) { throw OpenMM::OpenMMException("not yet on Reference"); }
    bool getPairVariable(int i, int j, double& value, long long& step) const { return false; }
    long long getNumPairVariables() const { return 0; }
};

} // namespace DPDPlugin

#endif
