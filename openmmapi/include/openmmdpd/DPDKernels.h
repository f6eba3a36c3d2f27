#ifndef OPENMMDPD_DPDKERNELS_H_
#define OPENMMDPD_DPDKERNELS_H_

#include "openmmdpd/DPDSoftRepulsionForce.h"
#include "openmmdpd/DPDVVIntegrator.h"
#include "openmmdpd/DenOtterClarkeIntegrator.h"
#include "openmmdpd/EDPDIntegrator.h"
#include "openmmdpd/LoweAndersenIntegrator.h"
#include "openmmdpd/MDPDForce.h"
#include "openmmdpd/ShardlowIntegrator.h"
#include "openmmdpd/StaggeredDPDIntegrator.h"
#include "openmm/KernelImpl.h"
#include "openmm/System.h"
#include <array>
#include <iosfwd>
#include <string>
#include <vector>

namespace DPDPlugin {

/**
 * What the step kernel of every DPD integrator answers, whatever its update rule.  The
 * kernel owns the per-Context integrator state (e.g. the force carried from one step to
 * the next), so it also writes and reads checkpoints.
 */
class DPDStepKernel : public OpenMM::KernelImpl {
public:
    DPDStepKernel(std::string name, const OpenMM::Platform& platform) : OpenMM::KernelImpl(name, platform) {}
    virtual double computeKineticEnergy(OpenMM::ContextImpl& context) = 0;
    /** Positions, velocities or parameters were changed from outside: carried forces are stale. */
    virtual void invalidateForces() = 0;
    virtual void createCheckpoint(OpenMM::ContextImpl& context, std::ostream& stream) const = 0;
    virtual void loadCheckpoint(OpenMM::ContextImpl& context, std::istream& stream) = 0;
    /** See DPDThermostatIntegrator::getAveragePressureTensor (part: a DPDThermostatIntegrator::PressurePart). */
    virtual std::vector<double> getAveragePressureTensor(int part) const = 0;
    virtual long long getPressureTensorSampleCount() const = 0;
    virtual void resetPressureTensor() = 0;
};

/**
 * The step kernel interface of one integrator class: initialize() and execute() take that
 * class, so no platform needs to find out which integrator it was given.
 */
template <class Integrator>
class TypedDPDStepKernel : public DPDStepKernel {
public:
    TypedDPDStepKernel(std::string name, const OpenMM::Platform& platform) : DPDStepKernel(name, platform) {}
    virtual void initialize(const OpenMM::System& system, const Integrator& integrator) = 0;
    /** Take one step. */
    virtual void execute(OpenMM::ContextImpl& context, const Integrator& integrator) = 0;
};

/** Takes steps of DPDVVIntegrator (GW-lambda, DPD-VV, SC-VV). */
class IntegrateDPDVVStepKernel : public TypedDPDStepKernel<DPDVVIntegrator> {
public:
    static std::string Name() { return "IntegrateDPDVVStep"; }
    IntegrateDPDVVStepKernel(std::string name, const OpenMM::Platform& platform) : TypedDPDStepKernel(name, platform) {}
};

/** Takes steps of ShardlowIntegrator (S1, S2). */
class IntegrateShardlowStepKernel : public TypedDPDStepKernel<ShardlowIntegrator> {
public:
    static std::string Name() { return "IntegrateShardlowStep"; }
    IntegrateShardlowStepKernel(std::string name, const OpenMM::Platform& platform) : TypedDPDStepKernel(name, platform) {}
};

/** Takes steps of LoweAndersenIntegrator (Lowe-Andersen, pair Ornstein-Uhlenbeck). */
class IntegrateLoweAndersenStepKernel : public TypedDPDStepKernel<LoweAndersenIntegrator> {
public:
    static std::string Name() { return "IntegrateLoweAndersenStep"; }
    IntegrateLoweAndersenStepKernel(std::string name, const OpenMM::Platform& platform) : TypedDPDStepKernel(name, platform) {}
};

/** Takes steps of StaggeredDPDIntegrator (both base schemes). */
class IntegrateStaggeredDPDStepKernel : public TypedDPDStepKernel<StaggeredDPDIntegrator> {
public:
    static std::string Name() { return "IntegrateStaggeredDPDStep"; }
    IntegrateStaggeredDPDStepKernel(std::string name, const OpenMM::Platform& platform) : TypedDPDStepKernel(name, platform) {}
};

/** Takes steps of DenOtterClarkeIntegrator, and answers for what they measured. */
class IntegrateDenOtterClarkeStepKernel : public TypedDPDStepKernel<DenOtterClarkeIntegrator> {
public:
    static std::string Name() { return "IntegrateDenOtterClarkeStep"; }
    IntegrateDenOtterClarkeStepKernel(std::string name, const OpenMM::Platform& platform) : TypedDPDStepKernel(name, platform) {}
    /** See DenOtterClarkeIntegrator::getMeasuredSums. */
    virtual void getMeasuredSums(double& sumFDDotV, double& sumFDDotFD, double& sumFRDotFR, long long& count) const = 0;
};

/** Takes steps of EDPDIntegrator, and answers for its pair variables. */
class IntegrateEDPDStepKernel : public TypedDPDStepKernel<EDPDIntegrator> {
public:
    static std::string Name() { return "IntegrateEDPDStep"; }
    IntegrateEDPDStepKernel(std::string name, const OpenMM::Platform& platform) : TypedDPDStepKernel(name, platform) {}
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
    /**
     * The force's pair virial at the Context's positions: the sum over pairs of r_ij,a F_ij,b
     * (kJ/mol, F_ij the force on i, r_ij = r_i - r_j the nearest image) as (xx, yy, zz, xy, xz, yz).
     */
    virtual std::array<double, 6> computeVirial(OpenMM::ContextImpl& context) = 0;
};

/** Computes the forces and energy of an MDPDForce: the local densities first, then the pair forces. */
class CalcMDPDForceKernel : public OpenMM::KernelImpl {
public:
    static std::string Name() { return "CalcMDPDForce"; }
    CalcMDPDForceKernel(std::string name, const OpenMM::Platform& platform) : OpenMM::KernelImpl(name, platform) {}
    virtual void initialize(const OpenMM::System& system, const MDPDForce& force) = 0;
    /** Add the forces to the Context's, if includeForces; return the energy (kJ/mol) if includeEnergy. */
    virtual double execute(OpenMM::ContextImpl& context, bool includeForces, bool includeEnergy) = 0;
    virtual void copyParametersToContext(OpenMM::ContextImpl& context, const MDPDForce& force) = 0;
    /** The pair virial at the Context's positions, as CalcDPDSoftRepulsionForceKernel::computeVirial's. */
    virtual std::array<double, 6> computeVirial(OpenMM::ContextImpl& context) = 0;
};

} // namespace DPDPlugin

#endif
