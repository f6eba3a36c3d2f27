#ifndef OPENMMDPD_DPDKERNELS_H_
#define OPENMMDPD_DPDKERNELS_H_

#include "openmmdpd/DPDVVIntegrator.h"
#include "openmm/KernelImpl.h"
#include "openmm/System.h"
#include <iosfwd>
#include <string>

namespace DPDPlugin {

/**
 * Takes steps with a DPDVVIntegrator.  The kernel owns the per-Context integrator state
 * (the force carried from one step to the next), so it also writes and reads checkpoints.
 */
class IntegrateDPDVVStepKernel : public OpenMM::KernelImpl {
public:
    static std::string Name() { return "IntegrateDPDVVStep"; }
    IntegrateDPDVVStepKernel(std::string name, const OpenMM::Platform& platform) : OpenMM::KernelImpl(name, platform) {}
    virtual void initialize(const OpenMM::System& system, const DPDVVIntegrator& integrator) = 0;
    virtual void execute(OpenMM::ContextImpl& context, const DPDVVIntegrator& integrator) = 0;
    virtual double computeKineticEnergy(OpenMM::ContextImpl& context, const DPDVVIntegrator& integrator) = 0;
    /** Positions, velocities or parameters were changed from outside: the carried force is stale. */
    virtual void invalidateForces() = 0;
    virtual void createCheckpoint(OpenMM::ContextImpl& context, std::ostream& stream) const = 0;
    virtual void loadCheckpoint(OpenMM::ContextImpl& context, std::istream& stream) = 0;
};

} // namespace DPDPlugin

#endif
