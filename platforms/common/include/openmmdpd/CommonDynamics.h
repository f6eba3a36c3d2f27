#ifndef OPENMMDPD_COMMONDYNAMICS_H_
#define OPENMMDPD_COMMONDYNAMICS_H_

#include "openmmdpd/CheckpointIO.h"
#include "openmmdpd/CommonCellList.h"
#include "openmmdpd/CommonPositionStrain.h"
#include "openmmdpd/PairParameters.h"
#include "openmmdpd/PairRandom.h"
#include "openmmdpd/PressureTensor.h"
#include "openmmdpd/StepState.h"
#include "openmm/internal/ContextImpl.h"
#include <cmath>
#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

namespace DPDPlugin {

/**
 * What the GPU platforms' update rules share (OpenMM's ComputeContext, so OpenCL and CUDA
 * alike): the thermostat parameters on the device, the cell list, the pair forces with
 * Philox numbers keyed as PairRandom's, the force carried from step to step (64-bit fixed
 * point, by atom index, so that a checkpoint holds it exactly) and the blow-up checks.  A
 * subclass writes one update rule in step(): CommonDPDVVDynamics (pair forces) or
 * CommonSweepDynamics (the sequential sweeps, on a grid of their own).
 *
 * OpenMM may reorder its particle slots inside a force evaluation: everything here that
 * lives across kernels is indexed by atom, read through OpenMM's atom index array.
 */
class CommonDynamics {
public:
    /**
     * Refuses (OpenMMException naming `platform`) what the device path does not do.
     * @param ruleSources     the kernel sources of the subclass's update rule
     * @param withPairForces  whether the rule uses pairForces (fd, fr, the cell list) and sumIntoCarried
     */
    CommonDynamics(OpenMM::ComputeContext& cc, const OpenMM::System& system, const DPDThermostatIntegrator& integrator,
                   const std::string& platform, const std::vector<std::string>& ruleSources, bool withPairForces);
    virtual ~CommonDynamics() {}
    double computeKineticEnergy(OpenMM::ContextImpl& context);
    void invalidateForces() { carried.invalidate(); }
    void updateParameters(const OpenMM::System& system, const DPDThermostatIntegrator& integrator);
    /**
     * The steps from now on add the virial of the thermostat's pair forces to `sink`, if not
     * null (PressureTensorSampler).
     */
    void recordThermostatVirial(SymmetricTensor* sink) { thermostatVirial = sink; }
    /** How the pressure tensor strains the positions. */
    PositionStrain& positionStrain() { return *strain; }
    void setSeed(uint32_t seed) { random = PairRandom(seed); }
    void createCheckpoint(std::ostream& stream) const;
    void loadCheckpoint(OpenMM::ContextImpl& context, CheckpointReader& reader);
    void resetState();
    /**
     * Throws an OpenMMException, naming the platform, for what the device path cannot do
     * (OpenMM's own periodic forces under shear or with the pressure tensor where OpenMM's
     * kernels take only a rectangular box); called before a Context is made and before every
     * step, so nothing has changed.
     */
    static void refuseUnsupported(const OpenMM::System& system, const DPDThermostatIntegrator& integrator, const std::string& platform);

protected:
    /** Whether the carried force holds for the Context's state (see CarriedForce). */
    bool carriedIsValid(OpenMM::ContextImpl& context);
    /** Copy velm (by slot) into `velocity` (by atom). */
    void gatherVelocities();
    /** OpenMM's forces of the groups into its force buffer (it may reorder the slots). */
    void conservativeForce(OpenMM::ContextImpl& context, int groups);
    /**
     * fd and/or fr (terms: 1, 2 or 3) of the pairs at the current positions, `velocity` the
     * velocities, the numbers keyed by step; the virial of the terms in virialTerms goes into
     * the step's thermostat virial while one is recorded (see startThermostatVirial).
     */
    void pairForces(long long step, double dt, int terms, bool rebuildCells = true, int virialTerms = 0);
    /** Start a step's thermostat virial on the device (if one is recorded). */
    void startThermostatVirial();
    /** Add the step's thermostat virial to the recorded one (if any). */
    void finishThermostatVirial();
    /**
     * virialRows as zeros, `rows` rows of 6 components `rows` apart: for a kernel that adds
     * its work items' virials to their rows.  Returns whether the array was reallocated (its
     * kernel argument must be set again).
     */
    bool clearVirialRows(int rows);
    /** The recorded thermostat virial += scale times the sum of virialRows' `rows` rows. */
    void addVirialRows(int rows, double scale);
    /**
     * With constraints, after a drift kernel left its moves in OpenMM's posDelta (and
     * driftMove): OpenMM's constraints correct them, the positions move, and each velocity,
     * and `velocity`, takes the correction / dt, as the Reference's ConstrainedMotion.
     */
    void constrainDrift(double dt, double tolerance);
    /** With constraints: OpenMM's velocity constraints on velm, and `velocity` gathered from it again. */
    void constrainVelocities(double tolerance);
    /** The drift kernels' arguments from `first`: whether they leave the moves to constrainDrift, posDelta and driftMove. */
    void addDriftArgs(OpenMM::ComputeKernel& kernel);
    /**
     * After a drift of duration dt, as the Reference's: the virtual sites placed from their
     * particles (OpenMM's IntegrationUtilities); under shear, the box slid and the molecules
     * that crossed brought back, with their velocity jumps (also in `velocity`, with
     * jumpVelocity), as LeesEdwardsBoundary::slide (kernels/leesEdwards.cc).
     */
    void finishDrift(double dt, bool jumpVelocity);
    /** carried = FC + FR (+ FD): the sums of the current pass. */
    void sumIntoCarried(bool withDissipative);
    /**
     * Throws the core's blow-up messages if a kernel of this step flagged a problem.  Called
     * once, at the end of a step (a read stalls the queue): the rest of a step that drifted a
     * position to a non-finite value only wastes work (the cell lists keep it inside their
     * grids), and the flags raised during it name the step, as the Reference's checks do.
     */
    void checkStatus(OpenMM::ContextImpl& context, long long step);
    /**
     * A rule's state beyond the carried force, in checkpoints after it: write it; read and
     * check it without using it; take it into use once the whole checkpoint is read; drop it.
     */
    virtual void saveExtraState(std::ostream&) const {}
    virtual void loadExtraState(CheckpointReader&) {}
    virtual void commitExtraState() {}
    virtual void resetExtraState() {}
    /** Sums FC (by slot) + FR (+ FD) into `out` (by atom), as sumIntoCarried into carriedForce. */
    void sumForcesInto(OpenMM::ComputeArray& out, bool withDissipative);
    /** A force component in OpenMM's 64-bit fixed point (2^32 per kJ/mol/nm) and back: exact below 2^21. */
    static double fromFixedForce(long long value) { return std::ldexp((double) value, -32); }
    static long long toFixedForce(double value) { return (long long) std::ldexp(value, 32); }
    /** Advance step count and time; let OpenMM reorder its slots for locality. */
    void finishStep(double dt);
    double velocityBound() const;
    double maxMove2() const;
    int numAtoms() const { return cc.getNumAtoms(); }

    OpenMM::ComputeContext& cc;
    const std::string name;  // "<integrator> on the <platform> platform"
    DPDPairParameters parameters;
    PairRandom random;
    CarriedForce carried;
    bool awaitingRestoreCheck = false;
    bool hasVirtualSites = false, hasConstraints = false;
    SymmetricTensor* thermostatVirial = nullptr;  // see recordThermostatVirial
    OpenMM::ComputeProgram program;
    std::unique_ptr<CommonPositionStrain> strain;
    std::unique_ptr<CommonCellList> cells;  // with pair forces only, as fd, fr, pairKernel and sumKernel
    OpenMM::ComputeArray atomType, typeParams, transverseParams, exceptionStart, exceptionPartner, exceptionFactor, velocity, fd, fr, carriedForce, status,
            moveValue, virialRows;
    OpenMM::ComputeKernel pairKernel, gatherKernel, sumKernel, findSlotsKernel, slideKernel, constrainedDriftKernel;
    OpenMM::ComputeArray driftMove;  // with constraints: each slot's move before they corrected it
    OpenMM::ComputeArray moleculeStart, moleculeAtoms, slotOf;  // for the sliding boundaries

private:
    /** finishDrift's shear part. */
    void slide(double dt, bool jumpVelocity);
    void uploadParameters();
    void createSlideKernels(const OpenMM::System& system);
    void createConstraintKernel();
    void createPairKernels();
};

} // namespace DPDPlugin

#endif
