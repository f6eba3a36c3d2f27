#ifndef OPENMMDPD_DPDKERNELS_H_
#define OPENMMDPD_DPDKERNELS_H_

#include "openmmdpd/DPDSoftRepulsionForce.h"
#include "openmmdpd/DPDThermostatIntegrator.h"
#include "openmm/KernelImpl.h"
#include "openmm/System.h"
#include <iosfwd>
#include <string>

namespace DPDPlugin {

/**
 * Takes steps with one of the DPD integrators.  Each integrator class has its own kernel
 * name; every platform implements them all with this interface.  The kernel owns the
 * per-Context integrator state (e.g. the force carried from one step to the next), so it
 * also writes and reads checkpoints.
 */
class IntegrateDPDStepKernel : public OpenMM::KernelImpl {
public:
    static std::string DPDVVName() { return "IntegrateDPDVVStep"; }
    static std::string ShardlowName() { return "IntegrateShardlowStep"; }
    static std::string LoweAndersenName() { return "IntegrateLoweAndersenStep"; }
    static std::string StaggeredName() { return "IntegrateStaggeredDPDStep"; }
    IntegrateDPDStepKernel(std::string name, const OpenMM::Platform& platform) : OpenMM::KernelImpl(name, platform) {}
    virtual void initialize(const OpenMM::System& system, const DPDThermostatIntegrator& integrator) = 0;
    virtual void execute(OpenMM::ContextImpl& context, const DPDThermostatIntegrator& integrator) = 0;
    virtual double computeKineticEnergy(OpenMM::ContextImpl& context) = 0;
    /** Positions, velocities or parameters were changed from outside: carried forces are stale. */
    virtual void invalidateForces() = 0;
    virtual void createCheckpoint(OpenMM::ContextImpl& context, std::ostream& stream) const = 0;
    virtual void loadCheckpoint(OpenMM::ContextImpl& context, std::istream& stream) = 0;
};

/** The step kernel of EDPDIntegrator, which also answers for its pair variables. */
class IntegrateEDPDStepKernel : public IntegrateDPDStepKernel {
public:
    static std::string Name() { return "IntegrateEDPDStep"; }
    IntegrateEDPDStepKernel(std::string name, const OpenMM::Platform& platform) : IntegrateDPDStepKernel(name, platform) {}
    /** The pair's s (kJ/mol/nm) and the step it belongs to; false if the pair is not remembered. */
    virtual bool getPairVariable(int i, int j, double& value, long long& step) const = 0;
    virtual long long getNumPairVariables() const = 0;
};

/** Computes the forces and energy of a DPDSoftRepulsionForce. */
class CalcDPDSoftRepulsionForceKernel : public OpenMM::KernelImpl {
public:
    static std::string Name() { return "CalcDPDSoftRepulsionForce"; }
    CalcDPDSoftRepulsionForceKernel(std::string name, const OpenMM::Platform& platform) : OpenMM::KernelImpl(name, platform) {}
    virtual void initialize(const OpenMM::System& system, const DPDSoftRepulsionForce& force) = 0;
    /** Add the forces to the Context's, if includeForces; return the energy (kJ/mol) if includeEnergy. */
    virtual double execute(OpenMM::ContextImpl& context, bool includeForces, bool includeEnergy) = 0;
    virtual void copyParametersToContext(OpenMM::ContextImpl& context, const DPDSoftRepulsionForce& force) = 0;
};

} // namespace DPDPlugin

#endif
