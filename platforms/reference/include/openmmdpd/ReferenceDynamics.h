#ifndef OPENMMDPD_REFERENCEDYNAMICS_H_
#define OPENMMDPD_REFERENCEDYNAMICS_H_

#include "openmmdpd/CheckpointIO.h"
#include "openmmdpd/ConstrainedMotion.h"
#include "openmmdpd/LeesEdwardsBoundary.h"
#include "openmmdpd/PressureTensor.h"
#include "openmmdpd/PairEvaluators.h"
#include "openmmdpd/PairParameters.h"
#include "openmmdpd/PairRandom.h"
#include "openmmdpd/ReferencePairList.h"
#include "openmmdpd/ReferencePositionStrain.h"
#include "openmmdpd/StepState.h"
#include "openmm/internal/ContextImpl.h"
#include "ReferencePlatform.h"
#include <iosfwd>
#include <string>
#include <vector>

namespace DPDPlugin {

/**
 * What the Reference platform's update rules share: the thermostat parameters, the pair
 * random numbers, the pairs at the current positions, the conservative force from the
 * Context, the force carried from one step to the next and its checkpoint.  Plain loops,
 * written to be read next to docs/theory/; a subclass writes one update rule in
 * step(context, integrator) of its integrator class.
 */
class ReferenceDynamics {
public:
    /** @param cellMultiple  see ReferencePairList (3 for the sequential sweeps) */
    ReferenceDynamics(const OpenMM::System& system, const DPDThermostatIntegrator& integrator, int cellMultiple);
    virtual ~ReferenceDynamics() {}
    double computeKineticEnergy(OpenMM::ContextImpl& context) const;
    void invalidateForces() { carried.invalidate(); }
    /** The integrator's thermostat parameters changed on a live Context: use them from now on. */
    void updateParameters(const OpenMM::System& system, const DPDThermostatIntegrator& integrator);
    /**
     * The steps from now on add the virial of the thermostat's pair forces (or of its sweeps'
     * pair impulses over dt) to `sink`, if not null (PressureTensorSampler).
     */
    void recordThermostatVirial(SymmetricTensor* sink) { thermostatVirial = sink; }
    /** How the pressure tensor strains the positions. */
    PositionStrain& positionStrain() { return strain; }
    /** The pair random numbers come from this seed from now on. */
    void setSeed(uint32_t seed) { random = PairRandom(seed); }
    void createCheckpoint(std::ostream& stream) const;
    /** Reads and checks the whole payload, then replaces the carried state with it. */
    void loadCheckpoint(OpenMM::ContextImpl& context, CheckpointReader& reader);
    /** Drops everything carried: the next step starts from the Context's state as a new Context would. */
    void resetState();

protected:
    /**
     * What a subclass carries beyond `carried` (written after it in a checkpoint): read and
     * check it in loadExtraState without using it, take it into use in commitExtraState,
     * drop it in resetExtraState.
     */
    virtual void saveExtraState(std::ostream& stream) const {}
    virtual void loadExtraState(CheckpointReader& reader) {}
    virtual void commitExtraState() {}
    virtual void resetExtraState() {}
    static OpenMM::ReferencePlatform::PlatformData& data(OpenMM::ContextImpl& context) {
        return *static_cast<OpenMM::ReferencePlatform::PlatformData*>(context.getPlatformData());
    }
    /** The thermostat pairs within their cutoffs at the current positions, in the sweep order. */
    std::vector<PairGeometry> findPairs(OpenMM::ContextImpl& context) const;
    /** The force of the given force groups at the current positions (from the Context). */
    std::vector<OpenMM::Vec3> conservativeForce(OpenMM::ContextImpl& context, int forceGroups, long long step) const;
    /**
     * out += FD_ij(v) (e.g. dissipative) and/or FR_ij, over the pairs; the numbers keyed by
     * step.  Their virial sum r_ij F_ij is added to `virial` if given.
     */
    void addDissipative(const std::vector<PairGeometry>& pairs, const std::vector<OpenMM::Vec3>& v,
                        std::vector<OpenMM::Vec3>& out, SymmetricTensor* virial = nullptr) const;
    void addRandom(const std::vector<PairGeometry>& pairs, long long step, double dt, std::vector<OpenMM::Vec3>& out,
                   SymmetricTensor* virial = nullptr) const;
    /**
     * The drift of a step of length dt ending at `step`: r += move[i] for every particle,
     * the blow-up checks, then the constraints and virtual sites (ConstrainedMotion::finishDrift,
     * which also corrects the velocities and `alsoCorrect`), and under shear the sliding
     * boundary (LeesEdwardsBoundary::slide, which gives them the jumps of the crossings).
     */
    void movePositions(OpenMM::ContextImpl& context, const std::vector<OpenMM::Vec3>& move, long long step, double dt,
                       std::vector<OpenMM::Vec3>* alsoCorrect = nullptr);
    /** After a velocity change: remove the velocity components along the constraints. */
    void constrainVelocities(OpenMM::ContextImpl& context) { motion.constrainVelocities(context); }
    /** sum m v^2. */
    double sumMV2(const std::vector<OpenMM::Vec3>& v) const;
    /**
     * End a step: the velocities must be finite (and under the instability threshold, see
     * checkVelocities); the Context's step count and time advance.
     */
    void finishStep(OpenMM::ContextImpl& context, double dt) const;

    const std::string name;
    DPDPairParameters parameters;
    PairRandom random;
    CarriedForce carried;
    SymmetricTensor* thermostatVirial = nullptr;  // see recordThermostatVirial
    ReferencePositionStrain strain;

private:
    /** out[i] += f, out[j] -= f for a pair force f along e (and its virial, if asked for). */
    void addPairForce(const PairGeometry& p, const OpenMM::Vec3& f, std::vector<OpenMM::Vec3>& out, SymmetricTensor* virial) const;
    ReferencePairList pairList;
    int cellMultiple;
    ConstrainedMotion motion;
    LeesEdwardsBoundary shear;
};

} // namespace DPDPlugin

#endif
