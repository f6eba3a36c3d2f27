#ifndef OPENMMDPD_DPDVVDYNAMICS_H_
#define OPENMMDPD_DPDVVDYNAMICS_H_

#include "openmmdpd/DPDVVIntegrator.h"
#include "openmmdpd/PairDynamics.h"

namespace DPDPlugin {

/**
 * The DPD velocity-Verlet family (docs/theory/velocity-verlet.md).  The carried force is the
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
    /**
     * DPD-VV's steps (4) and (5) (repeated for SC-VV) after the pass of step (3), in its
     * outputs' order: by particle (the velocities themselves, constrained), or by slot (a copy,
     * returned, for the caller to put back into particle order once).
     */
    const std::vector<OpenMM::Vec3>& updateVelocities(OpenMM::ContextImpl& context, const DPDVVIntegrator& integrator, bool bySlot);
    /** Whether DPD-VV's steps (4) and (5) can run in the slot order of the pair search: no constraints, every particle thermostatted. */
    bool canStayInSlotOrder() const;
    /** The inverse masses (and masses, if asked) in the slot order of the last search. */
    void sortMasses(bool withMasses);
    // By particle, or by slot where canStayInSlotOrder.
    std::vector<OpenMM::Vec3> dissipative, conservativeAndRandom, velocityNoFD;
    std::vector<OpenMM::Vec3> predicted, newForce, slotVelocities;
    std::vector<double> slotInverseMasses, slotMasses;
};

} // namespace DPDPlugin

#endif
