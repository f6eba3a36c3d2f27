#ifndef OPENMMDPD_STAGGEREDDPDINTEGRATOR_H_
#define OPENMMDPD_STAGGEREDDPDINTEGRATOR_H_

#include "openmmdpd/DPDThermostatIntegrator.h"
#include <vector>

namespace OpenMM {
class System;
}

namespace DPDPlugin {

/**
 * Symeonidis and Karniadakis' time-staggered multi-timestep DPD (2006, Tables 1
 * and 2; docs/theory/staggered.md) for stiff polymers in a soft DPD solvent.
 *
 * The step size is the outer step Dt.  Once per outer step the "slow" forces are evaluated
 * for every particle: the conservative forces of the integration force groups that are not
 * fast, plus (velocity-Verlet base) the dissipative and random pair forces of this
 * integrator's type-pair table.  The polymer particles are then sub-cycled K =
 * numSubSteps times with the sub-step dt = Dt/K, re-evaluating only the fast (stiff)
 * forces; solvent particles take one velocity-Verlet step of Dt and never pay for a
 * sub-step.  One call of step(1) advances the Context by Dt (its step count by one).
 *
 * Base schemes:
 * - VelocityVerlet: Groot-Warren velocity Verlet with velocity-prediction parameter
 *   lambda (Table 1).  The friction parameters are friction rates (1/ps), as for
 *   DPDVVIntegrator.
 * - LoweAndersen: velocity Verlet with the conservative forces and, once at the end of the
 *   outer step, Lowe-Andersen's pair thermalisation with probability Gamma Dt (Table 2).
 *   The friction parameters are then the collision rates Gamma (1/ps), and Gamma Dt must be
 *   <= 1.  The pairs thermalised, their distances and directions are those at the
 *   end-of-step positions (the polymer's after its sub-cycle), searched for there, not at
 *   the provisional polymer positions the slow forces were evaluated at.
 *
 * Relaxation parameters (each in [-1, 1]; 0 uses the prediction, 1 the old value):
 * mu for the polymer positions the slow forces are evaluated at, a for the polymer
 * velocities they are evaluated with (velocity-Verlet base only), b for the slow force that
 * drives the polymer positions in the sub-steps.  Weighted staggering interpolates the slow
 * force linearly in time across the sub-steps; non-weighted uses the old and the new one.
 *
 * With K = 1, the scheme is GrootWarren (DPDVVIntegrator) or Lowe (LoweAndersenIntegrator)
 * exactly (to rounding, same seed) when (mu, a, b) = (0, 0, 1): b = 1 drives the positions
 * with the force of the positions they started from, as velocity Verlet does.  The
 * paper's baseline (0, 0, 0) drives them with the predicted force instead and is a
 * different scheme even at K = 1.
 *
 * Fast forces and polymer particles are said the OpenMM way: the fast forces are those of
 * the force groups in fastForceGroups (a bitmask like the integration force groups; group 1
 * by default).  The polymer particles are the explicit list when one was given
 * (setPolymerParticles, addPolymerParticle); otherwise they are derived from the System
 * when a Context is created: every particle of a term of a force in a fast group that lists
 * the particles of its terms -- a bond, angle, torsion or compound bond (HarmonicBond,
 * HarmonicAngle, PeriodicTorsion, RBTorsion, CMAPTorsion, CustomBond, CustomAngle,
 * CustomTorsion, CustomCompoundBond), a bond of a CustomCentroidBondForce (every particle
 * of its groups), a particle of a CustomExternalForce, a donor or acceptor of a
 * CustomHbondForce, or an interaction group of a CustomNonbondedForce.  Any other force in
 * a fast group (a NonbondedForce, a CustomNonbondedForce without interaction groups, ...:
 * forces that act on every particle their parameters switch on) makes the derivation fail
 * with an exception asking for the explicit list.
 *
 * The fast forces must act on polymer particles only.  When a Context is created (and when
 * the explicit list or the fast groups change), every particle of every term of those
 * forces must be in an explicit list, else an OpenMMException names the force, the term and
 * the particle.  A force that lists no particles cannot be checked there; with one in a fast
 * group, the platforms check at every evaluation of the fast forces that they leave the
 * other particles alone (fastForcesListTheirParticles()).
 *
 * Cost: for K > 1 the fast forces are evaluated in a second Context holding only the
 * polymer particles and copies of the fast forces (HarmonicBond, CustomBond, and
 * CustomNonbonded with interaction groups can be copied; otherwise the fast groups are
 * evaluated in the Context itself), on the Reference platform for a small polymer (a
 * CustomNonbondedForce there as bonds over Verlet-listed pairs) and on the Context's
 * platform otherwise, and the slow forces in a third one holding the System without its fast
 * forces, on the Context's platform with its properties; both are kept in step with its
 * positions, box and global parameters.  K = 1 uses the Context alone.
 *
 * The defaults are Symeonidis and Karniadakis' (2006) recommendation for the velocity-Verlet
 * base: weighted, (mu, a, b) = (0, 0.6, 0), lambda = 0.65.  useRecommendedParameters() applies
 * the recommendation of the current base scheme (Lowe: weighted, (0, 0, 0.4)).
 */
class StaggeredDPDIntegrator : public DPDThermostatIntegrator {
public:
    enum BaseScheme {
        VelocityVerlet = 0,
        LoweAndersen = 1
    };
    /**
     * @param temperature      the temperature of the heat bath (K)
     * @param defaultFriction  the friction rate (velocity Verlet) or collision rate Gamma
     *                         (Lowe-Andersen) of pairs without a type-pair entry (1/ps)
     * @param defaultCutoff    the thermostat cutoff of pairs without a type-pair entry (nm)
     * @param stepSize         the outer step Dt (ps)
     * @param numSubSteps      K, the number of polymer sub-steps per outer step (1 to MAX_SUB_STEPS)
     */
    StaggeredDPDIntegrator(double temperature, double defaultFriction, double defaultCutoff, double stepSize, int numSubSteps = 1);
    BaseScheme getBaseScheme() const { return baseScheme; }
    /** Set the base scheme; it changes nothing else (see useRecommendedParameters()). */
    void setBaseScheme(BaseScheme scheme);
    /** Get K, the number of polymer sub-steps per outer step. */
    int getNumSubSteps() const { return numSubSteps; }
    /** The largest K: each sub-step evaluates the fast forces, so more would only look like a hang. */
    static constexpr int MAX_SUB_STEPS = 10000;
    /** Set K, from 1 to MAX_SUB_STEPS. */
    void setNumSubSteps(int steps);
    /** The polymer sub-step dt = Dt/K (ps). */
    double getSubStepSize() const { return getStepSize() / numSubSteps; }
    /** Get Groot and Warren's velocity-prediction parameter (velocity-Verlet base). */
    double getLambda() const { return lambda; }
    /** Set lambda, in [0, 1]. */
    void setLambda(double value);
    /** Get the relaxation parameter of the polymer positions the slow forces are evaluated at. */
    double getMu() const { return mu; }
    /** Set mu, in [-1, 1]. */
    void setMu(double value);
    /** Get the relaxation parameter of the polymer velocities the slow forces are evaluated with. */
    double getA() const { return a; }
    /** Set a (the paper's alpha), in [-1, 1]. */
    void setA(double value);
    /** Get the relaxation parameter of the slow force that drives the sub-step positions. */
    double getB() const { return b; }
    /** Set b (the paper's beta), in [-1, 1]. */
    void setB(double value);
    /** Set mu, a and b at once (each in [-1, 1]; nothing changes unless all are valid). */
    void setRelaxationParameters(double mu, double a, double b);
    /** Whether the slow force is interpolated linearly across the sub-steps. */
    bool getWeighted() const { return weighted; }
    void setWeighted(bool value) { weighted = value; }
    /** Get the force groups of the fast forces, a bitmask (bit g set: group g is fast). */
    int getFastForceGroups() const { return fastForceGroups; }
    /** Set the fast force groups: non-zero, and a subset of the integration force groups. */
    void setFastForceGroups(int groups);
    /**
     * Symeonidis and Karniadakis' (2006) recommendation for the current base scheme: weighted
     * staggering with (mu, a, b) = (0, 0.6, 0) and lambda = 0.65 (velocity Verlet), or
     * (0, 0, 0.4) (Lowe).
     */
    void useRecommendedParameters();
    /** The explicit polymer particles (empty: derived from the fast forces). */
    const std::vector<int>& getPolymerParticles() const { return polymerParticles; }
    /** Set the polymer particles explicitly (an empty list returns to deriving them). */
    void setPolymerParticles(const std::vector<int>& particles);
    /** Add one particle to the explicit polymer particles. */
    void addPolymerParticle(int particle);
    /**
     * The polymer particles a Context for this System sub-cycles, in increasing order: the
     * explicit list, or those derived from the fast forces (see the class description).
     * Throws an OpenMMException if they cannot be derived, or if the explicit list misses a
     * particle of a term of a fast force.
     */
    std::vector<int> findPolymerParticles(const OpenMM::System& system) const;
    /**
     * Whether every force in a fast group lists the particles of its terms, so that
     * findPolymerParticles() checks all of them.  If not (possible with an explicit list
     * only), the platforms check the fast forces on the other particles at every evaluation.
     */
    bool fastForcesListTheirParticles(const OpenMM::System& system) const;
    /**
     * Also requires a force in a fast group, fast groups within the integration force
     * groups, valid polymer particle indices and, for the Lowe base, Gamma Dt <= 1.
     */
    void validate(const OpenMM::System& system) const override;

protected:
    /** Its steps do not sample the pressure tensor (yet). */
    bool supportsPressureTensor() const override { return false; }
    std::string kernelName() const override;
    void initializeStepKernel(OpenMM::Kernel& kernel, const OpenMM::System& system) const override;
    void executeStepKernel(OpenMM::Kernel& kernel, OpenMM::ContextImpl& context) const override;

private:
    BaseScheme baseScheme;
    int numSubSteps, fastForceGroups;
    double lambda, mu, a, b;
    bool weighted;
    std::vector<int> polymerParticles;
};

} // namespace DPDPlugin

#endif
