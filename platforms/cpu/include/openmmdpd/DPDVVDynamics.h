#ifndef OPENMMDPD_DPDVVDYNAMICS_H_
#define OPENMMDPD_DPDVVDYNAMICS_H_

#include "openmmdpd/DPDVVIntegrator.h"
#include "openmmdpd/PairDynamics.h"

namespace DPDPlugin {

/**
 * The DPD velocity-Verlet family (algorithms.md section 1).  The carried force is the
 * total force F = FC + FD + FR at the current state.
 */
class DPDVVDynamics : public PairDynamics {
public:
    DPDVVDynamics(const OpenMM::System& system, const DPDVVIntegrator& integrator, ParallelExecutor& executor);
    void step(OpenMM::ContextImpl& context, const DPDVVIntegrator& integrator);

private:
    /** F <- FC + FD(v) + FR, at the current state (a start, or after outside changes). */
    void computeInitialForce(OpenMM::ContextImpl& context, const DPDVVIntegrator& integrator);
    void grootWarrenStep(OpenMM::ContextImpl& context, const DPDVVIntegrator& integrator);
    void dpdvvStep(OpenMM::ContextImpl& context, const DPDVVIntegrator& integrator);
    std::vector<OpenMM::Vec3> dissipative, conservativeAndRandom, predicted, velocityNoFD, newForce;
};

} // namespace DPDPlugin

#endif
