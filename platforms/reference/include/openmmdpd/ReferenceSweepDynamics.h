#ifndef OPENMMDPD_REFERENCESWEEPDYNAMICS_H_
#define OPENMMDPD_REFERENCESWEEPDYNAMICS_H_

#include "openmmdpd/LoweAndersenIntegrator.h"
#include "openmmdpd/ReferenceDynamics.h"
#include "openmmdpd/ShardlowIntegrator.h"
#include "openmm/OpenMMException.h"

namespace DPDPlugin {

// PLACEHOLDER (to be written): Shardlow S1/S2 and Lowe-Andersen/pair OU.
class ReferenceShardlowDynamics : public ReferenceDynamics {
public:
    ReferenceShardlowDynamics(const OpenMM::System& system, const ShardlowIntegrator& integrator) : ReferenceDynamics(system, integrator, 3) {}
    void step(OpenMM::ContextImpl&, const ShardlowIntegrator&) { throw OpenMM::OpenMMException("not yet on Reference"); }
};

class ReferenceLoweAndersenDynamics : public ReferenceDynamics {
public:
    ReferenceLoweAndersenDynamics(const OpenMM::System& system, const LoweAndersenIntegrator& integrator) : ReferenceDynamics(system, integrator, 3) {}
    void step(OpenMM::ContextImpl&, const LoweAndersenIntegrator&) { throw OpenMM::OpenMMException("not yet on Reference"); }
};

} // namespace DPDPlugin

#endif
