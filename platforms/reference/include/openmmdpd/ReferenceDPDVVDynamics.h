#ifndef OPENMMDPD_REFERENCEDPDVVDYNAMICS_H_
#define OPENMMDPD_REFERENCEDPDVVDYNAMICS_H_

#include "openmmdpd/DPDVVIntegrator.h"
#include "openmmdpd/ReferenceDynamics.h"

namespace DPDPlugin {

/**
 * The DPD velocity-Verlet family (docs/theory/velocity-verlet.md): Groot-Warren with lambda,
 * DPD-VV and SC-VV.  The carried force is F = FC + FD + FR of the last evaluation.
 */
class ReferenceDPDVVDynamics : public ReferenceDynamics {
public:
    ReferenceDPDVVDynamics(const OpenMM::System& system, const DPDVVIntegrator& integrator) : ReferenceDynamics(system, integrator, 1) {}
    void step(OpenMM::ContextImpl& context, const DPDVVIntegrator& integrator);

private:
    /** FC + FD(v) + FR at the current positions, the random numbers keyed by step (FD + FR's virial added to `virial` if given). */
    std::vector<OpenMM::Vec3> totalForce(OpenMM::ContextImpl& context, const DPDVVIntegrator& integrator,
                                         const std::vector<OpenMM::Vec3>& v, long long step, SymmetricTensor* virial = nullptr);
    void grootWarrenStep(OpenMM::ContextImpl& context, const DPDVVIntegrator& integrator);
    void dpdvvStep(OpenMM::ContextImpl& context, const DPDVVIntegrator& integrator);
};

} // namespace DPDPlugin

#endif
