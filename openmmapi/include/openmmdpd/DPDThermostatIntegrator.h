#ifndef OPENMMDPD_DPDTHERMOSTATINTEGRATOR_H_
#define OPENMMDPD_DPDTHERMOSTATINTEGRATOR_H_

#include "openmmdpd/ParticleTypeTable.h"
#include "openmm/Integrator.h"
#include "openmm/Kernel.h"
#include <map>
#include <vector>

namespace DPDPlugin {

/** Boltzmann's constant in kJ/mol/K (OpenMM's value). */
constexpr double BOLTZMANN_KJ_PER_MOL_K = 0.00831446261815324;

/** The relative tolerance of constraints a new integrator starts with (OpenMM's integrators' default). */
constexpr double DEFAULT_CONSTRAINT_TOLERANCE = 1e-5;

/**
 * The parameters every DPD-style pair thermostat shares: temperature, the per-type-pair
 * friction and cutoff table, particle types and the random number seed.  Concrete
 * integrators (DPDVVIntegrator, ...) add their own update rule on top.
 *
 * The parameter model mirrors OpenMM 8.3's DPDIntegrator so that scripts can switch by
 * class name.  A pair (i, j) with types (ti, tj) uses the parameters given to
 * addTypePair(ti, tj, ...) if such an entry exists, and the defaults otherwise.
 *
 * It also owns the plumbing every such integrator shares with OpenMM (binding to a
 * Context, stepping, kinetic energy, checkpoints): a subclass names its kernel and adds
 * its own parameters and checks.
 *
 * Friction is a rate in 1/ps.  The pair friction coefficient of the DPD equations is
 * gamma_ij = 2 mu_ij friction (amu/ps), with mu_ij = m_i m_j / (m_i + m_j) the pair's
 * reduced mass, so friction = gamma for unit masses; the noise amplitude follows from
 * fluctuation-dissipation: sigma_ij^2 = 2 gamma_ij kT.
 */
class DPDThermostatIntegrator : public OpenMM::Integrator {
public:
    /**
     * @param className        the subclass's name, which every error message starts with
     * @param temperature      the temperature of the heat bath (K)
     * @param defaultFriction  the friction rate of pairs without a type-pair entry (1/ps)
     * @param defaultCutoff    the thermostat cutoff of pairs without a type-pair entry (nm)
     * @param stepSize         the step size (ps)
     */
    DPDThermostatIntegrator(const std::string& className, double temperature, double defaultFriction, double defaultCutoff,
                            double stepSize);
    /** Get the temperature of the heat bath (K). */
    double getTemperature() const { return temperature; }
    /** Set the temperature of the heat bath (K); must be >= 0. */
    void setTemperature(double temp);
    /** Get the default friction rate (1/ps). */
    double getDefaultFriction() const { return defaultFriction; }
    /** Set the default friction rate (1/ps); must be >= 0. */
    void setDefaultFriction(double friction);
    /** Get the default thermostat cutoff (nm). */
    double getDefaultCutoff() const { return defaultCutoff; }
    /** Set the default thermostat cutoff (nm); must be > 0. */
    void setDefaultCutoff(double cutoff);
    /** Set the step size (ps); must be > 0. */
    void setStepSize(double size) override;
    /**
     * Set the relative tolerance to which constraints are satisfied; must be > 0 (and < 1).
     * A new integrator has DEFAULT_CONSTRAINT_TOLERANCE.
     */
    void setConstraintTolerance(double tol) override;
    /** Get the type of a particle (0 unless set). */
    int getParticleType(int index) const { return types.getParticleType(index); }
    /** Set the type of a particle; types are integers >= 0. */
    void setParticleType(int index, int type) {
        types.setParticleType(index, type);
        parametersVersion++;
    }
    /** Get every particle type that was set explicitly, by particle index. */
    const std::map<int, int>& getParticleTypes() const { return types.getParticleTypes(); }
    /**
     * Add parameters for pairs of particles with types type1 and type2 (in either order).
     *
     * @param friction  the friction rate of such pairs (1/ps), >= 0
     * @param cutoff    the thermostat cutoff of such pairs (nm), > 0
     * @return the index of the type pair
     */
    int addTypePair(int type1, int type2, double friction, double cutoff) {
        const int index = types.addTypePair(type1, type2, friction, cutoff);
        parametersVersion++;
        return index;
    }
    /** Get the number of type pairs that were added. */
    int getNumTypePairs() const { return types.getNumTypePairs(); }
    /** Get the parameters of a type pair (friction in 1/ps, cutoff in nm). */
    void getTypePairParameters(int pairIndex, int& type1, int& type2, double& friction, double& cutoff) const;
    /** Set the parameters of a type pair (friction in 1/ps, cutoff in nm). */
    void setTypePairParameters(int pairIndex, int type1, int type2, double friction, double cutoff) {
        types.setTypePair(pairIndex, type1, type2, friction, cutoff);
        parametersVersion++;
    }
    /**
     * Get the default weight exponent s: pairs without an exponent of their own have the
     * dissipative weight wD = (1 - r/rc)^s and the random weight wR = (1 - r/rc)^(s/2)
     * (docs/theory/dpd.md).  2, the default, is standard DPD.
     */
    double getDefaultWeightExponent() const { return defaultWeightExponent; }
    /**
     * Set the default weight exponent s, > 0 (see getDefaultWeightExponent()).  s < 2 weights
     * the friction of distant pairs more, which raises the fluid's viscosity and Schmidt
     * number (Fan et al. 2006); the conservative force is untouched.
     */
    void setDefaultWeightExponent(double s);
    /** Get the weight exponent of a type pair: its own if set, else the default. */
    double getTypePairWeightExponent(int pairIndex) const;
    /** Set the weight exponent s of a type pair, > 0 (see getDefaultWeightExponent()). */
    void setTypePairWeightExponent(int pairIndex, double s);
    /** Whether every pair has the standard weight exponent 2 (the default and every type pair's). */
    bool hasStandardWeights() const;
    /**
     * Get the default transverse friction rate (1/ps; 0, the default, means none): friction
     * on the part of a pair's relative velocity perpendicular to e = r_ij / r, with its own
     * random force that keeps fluctuation-dissipation (Junghans, Praprotnik and Kremer 2008;
     * docs/theory/dpd.md).  Its coefficient is 2 mu_ij times the rate, as for the friction
     * along e, and its weights are wD = (1 - r/rc)^s, wR = (1 - r/rc)^(s/2) with the transverse
     * exponent s.  It raises the viscosity (and the Schmidt number) without changing the
     * equilibrium; the pair force is then not central (angular momentum is not conserved).
     * DPDVVIntegrator, ShardlowIntegrator and LoweAndersenIntegrator's pair Ornstein-Uhlenbeck
     * method have it.
     */
    double getDefaultTransverseFriction() const { return defaultTransverseFriction; }
    /** Set the default transverse friction rate (1/ps), >= 0 (see getDefaultTransverseFriction()). */
    void setDefaultTransverseFriction(double friction);
    /** Get the default transverse weight exponent s (2 unless set; see getDefaultTransverseFriction()). */
    double getDefaultTransverseWeightExponent() const { return defaultTransverseWeightExponent; }
    /** Set the default transverse weight exponent s, > 0. */
    void setDefaultTransverseWeightExponent(double s);
    /**
     * Get the transverse friction rate (1/ps) and its weight exponent of a type pair: its own
     * if set, else the defaults.
     */
    void getTypePairTransverseFriction(int pairIndex, double& friction, double& weightExponent) const;
    /** Set the transverse friction rate (1/ps, >= 0) and its weight exponent (> 0) of a type pair. */
    void setTypePairTransverseFriction(int pairIndex, double friction, double weightExponent);
    /** Whether any pair has transverse friction (the default or a type pair's is not 0). */
    bool hasTransverseFriction() const;
    /**
     * Scale the thermostat of one pair of particles (docs/theory/dpd.md): its friction by
     * factor and its noise amplitude by sqrt(factor), which keeps fluctuation-dissipation;
     * factor 0 excludes the pair from the thermostat (for Lowe-Andersen collisions: their
     * probability is scaled).  The conservative forces are untouched.
     *
     * @param factor  in [0, 1]
     * @return the index of the exception
     */
    int addThermostatException(int particle1, int particle2, double factor);
    /** Get the number of thermostat exceptions. */
    int getNumThermostatExceptions() const { return (int) exceptions.size(); }
    /** Get the particles and factor of a thermostat exception. */
    void getThermostatExceptionParameters(int index, int& particle1, int& particle2, double& factor) const;
    /** Set the particles and factor of a thermostat exception (factor in [0, 1]). */
    void setThermostatExceptionParameters(int index, int particle1, int particle2, double factor);
    /**
     * Add a thermostat exception for every pair of particles one bond apart (factor12) and two
     * bonds apart (factor13, if it is not 1) in `bonds`, pairs of particle indices (in Python a
     * list of (i, j) tuples), as NonbondedForce::createExceptionsFromBonds does for its 1-2
     * and 1-3 pairs; a factor of 1 adds none for its pairs.  Refused, changing nothing, if a
     * pair already has one.
     */
    void createThermostatExceptionsFromBonds(const std::vector<std::pair<int, int>>& bonds, double factor12, double factor13);
    /**
     * Get the random number seed.  0 (the default) means that a new seed is chosen each
     * time a Context is created; it is then kept in checkpoints.
     */
    int getRandomNumberSeed() const { return randomNumberSeed; }
    /**
     * Set the random number seed (see getRandomNumberSeed()).  On a live Context the pair
     * random numbers come from the new seed from the next step on (0: a new seed is chosen).
     */
    void setRandomNumberSeed(int seed) {
        randomNumberSeed = seed;
        seedVersion++;
    }
    /**
     * Get the instability threshold, as a multiple of kT (0, the default, means off); see
     * setInstabilityThreshold().
     */
    double getInstabilityThreshold() const { return instabilityThreshold; }
    /**
     * Set the instability threshold: a step after which any particle has a kinetic energy
     * m v^2 / 2 above factor kT (kT of the current temperature) stops the run with an
     * OpenMMException "... the simulation is unstable at step N ...", instead of letting a
     * transient blow-up (bonds stretched far, a local temperature spike, then recovery) pass
     * into the averages.  Every step always checks that velocities and positions are finite
     * and that no particle jumps several cutoffs; this catches what those miss.
     *
     * 40 is the recommended value: in a Maxwell-Boltzmann fluid a particle exceeds x kT with
     * probability 2 sqrt(x/pi) exp(-x) + erfc(sqrt(x)) ~ 3e-17 per step for x = 40, so a false
     * alarm over 10^12 particle-steps has odds ~3e-5 (~0.3 in a fluid running 30 % too hot),
     * while the polymer scene's transient blow-ups at too large a step put beads at 40-250 kT.
     * The check shares the end-of-step loop over the velocities with the finiteness check, so
     * it costs next to nothing.  With
     * temperature 0 there is no kT to compare against and the check is off.
     *
     * @param factor  the threshold as a multiple of kT, >= 0 (0 turns the check off)
     */
    void setInstabilityThreshold(double factor);
    /** Get the shear rate of the Lees-Edwards boundaries (1/ps; 0, the default, means no shear). */
    double getShearRate() const { return shearRate; }
    /**
     * Shear the System with Lees-Edwards boundaries (docs/theory/lees-edwards.md): flow along x,
     * gradient along y, the image above the box sliding at U = rate Ly along x.  The sliding
     * image is the Context's triclinic box b = (offset, Ly, 0): every step advances the offset
     * by U times the time drifted (reduced to OpenMM's range |offset| <= Lx/2), so every
     * periodic OpenMM Force works unchanged.  The integrator owns the rest: a molecule
     * whose centre leaves through y = Ly (or 0) re-enters through the other side, shifted by
     * -b (+b) and with its x velocity lowered (raised) by U, and every thermostat pair
     * across the boundary sees its partner's image moving at +-U.  Velocities stay those of
     * the lab frame (computeKineticEnergy() included); the streaming velocity at height y is
     * rate (y - Ly/2).  Needs a periodic System whose third box vector is (0, 0, Lz) and whose
     * Forces are periodic or bonded (a bonded force sees its molecule wrapped as a whole).
     * Takes effect on a live Context at the next step.
     *
     * @param rate  the shear rate (1/ps), finite; its sign sets the direction of the flow
     */
    void setShearRate(double rate);
    /** The parts of the pressure tensor (getAveragePressureTensor). */
    enum PressurePart {
        /** Their sum, the whole pressure tensor. */
        PressureTotal = 0,
        /** sum m u u / V, u the peculiar velocity v - rate (y - Ly/2) x less the centre-of-mass velocity. */
        PressureKinetic = 1,
        /** The virial of the integration force groups' forces, / V. */
        PressureConservative = 2,
        /** The virial of the dissipative and random pair forces (or pair impulses / dt), / V. */
        PressureThermostat = 3
    };
    /** Get whether every step adds a sample to the pressure tensor (false by default). */
    bool getPressureTensorEnabled() const { return pressureTensorEnabled; }
    /**
     * Sample the pressure tensor at the end of every step from now on
     * (docs/theory/pressure-tensor.md): P = (1/V) [sum_i m_i u_i u_i
     * + sum_{i<j} r_ij (FC + FD + FR)_ij], with the
     * dissipative and random parts from the pair forces the step applied (for a scheme
     * that sweeps pairs sequentially, the impulses J_ij of its sweeps: sum r_ij J_ij / dt).
     * The conservative virial is exact for a force group that holds only
     * DPDSoftRepulsionForces, and otherwise -dU/d(strain) by central differences of the
     * groups' energy over an affine strain of the box and every particle (atomic virial; 12
     * energy evaluations per step, so put a DPDSoftRepulsionForce in a group of its own).
     * Costs an extra pass over the pairs per step; off, it costs nothing and no trajectory
     * depends on it.  Not available with constraints, whose forces it leaves out.
     */
    void setPressureTensorEnabled(bool enabled);
    /**
     * Get the pressure tensor averaged over the steps sampled since the Context was created
     * or resetPressureTensor() was last called, as (xx, yy, zz, xy, xz, yz) in kJ/mol/nm^3
     * (positive is compressive; under shear the viscosity is -P_xy / rate).
     *
     * @param part  a PressurePart: the whole tensor (default) or one of its parts
     */
    std::vector<double> getAveragePressureTensor(int part = PressureTotal) const;
    /** Get the number of steps averaged by getAveragePressureTensor(). */
    long long getPressureTensorSampleCount() const;
    /** Start a new average of the pressure tensor. */
    void resetPressureTensor();
    /** The largest thermostat cutoff over the defaults and all type pairs (nm). */
    double getMaxCutoff() const { return types.getMaxCutoff(defaultCutoff); }
    /** The largest friction over the defaults and all type pairs (1/ps). */
    double getMaxFriction() const { return types.getMaxValue(defaultFriction); }
    /**
     * Changes whenever a thermostat parameter does (temperature, friction, cutoffs, types,
     * type pairs, weight exponents, transverse friction, the instability threshold, the shear rate): the step kernels take such changes into a live
     * Context at the next step.
     */
    int getThermostatParametersVersion() const { return parametersVersion; }
    /** Changes whenever setRandomNumberSeed() is called: the step kernels reseed at the next step. */
    int getRandomNumberSeedVersion() const { return seedVersion; }
    /** Advance the simulation by a number of steps. */
    void step(int steps) override;

    /** The name used in error messages, e.g. "DPDVVIntegrator". */
    const char* className() const { return name.c_str(); }
    /**
     * Throw an OpenMMException unless the parameters are consistent with each other and
     * with the System; called when a Context is created and before every step.
     */
    virtual void validate(const OpenMM::System& system) const;

protected:
    /** The name of the kernel that takes the steps. */
    virtual std::string kernelName() const = 0;
    /**
     * Whether this integrator's steps sample the pressure tensor; setPressureTensorEnabled(true)
     * is refused otherwise.
     */
    virtual bool supportsPressureTensor() const { return true; }
    /**
     * Throw an OpenMMException unless this integrator's scheme, as set, has transverse friction
     * for this System (called by validate() where a pair has any); by default it has none.
     */
    virtual void validateTransverseFriction(const OpenMM::System& system) const;
    /** The refusal of transverse friction with constraints, for the schemes that sweep pairs: their impulses are along e there. */
    void refuseTransverseFrictionWithConstraints(const OpenMM::System& system) const;
    /** Initialize the step kernel (of this class's typed interface) for a System. */
    virtual void initializeStepKernel(OpenMM::Kernel& kernel, const OpenMM::System& system) const = 0;
    /** Take one step with the step kernel. */
    virtual void executeStepKernel(OpenMM::Kernel& kernel, OpenMM::ContextImpl& context) const = 0;
    void initialize(OpenMM::ContextImpl& context) override;
    void cleanup() override;
    std::vector<std::string> getKernelNames() override;
    void stateChanged(OpenMM::State::DataType changed) override;
    double computeKineticEnergy() override;
    void createCheckpoint(std::ostream& stream) const override;
    void loadCheckpoint(std::istream& stream) override;
    /** The kernel that takes the steps (throws unless bound to a Context). */
    const OpenMM::Kernel& getStepKernel() const;

private:
    void checkTemperature(double temp) const;
    void checkFriction(double friction) const;
    void checkCutoff(double cutoff) const;
    void checkWeightExponent(const std::string& parameter, double s) const;
    void checkTransverseFriction(const std::string& parameter, double friction) const;
    /** A valid exception that is not a second one for its pair (`replacing`: the index it replaces, or -1). */
    void checkException(int particle1, int particle2, double factor, int replacing) const;
    void checkStepSize(double size) const;
    /** Under shear: a periodic System with c = (0, 0, Lz) whose Forces are periodic or bonded. */
    void validateShear(const OpenMM::System& system) const;
    /** Under shear: the third vector of a box (`which`, for the message) must be (0, 0, Lz). */
    void validateShearBox(const OpenMM::Vec3* box, const std::string& which) const;
    /** The Context's current box, which may differ from the System's default: the cutoff fits, and the shear's form. */
    void validateContextBox() const;
    std::string name;
    double temperature, defaultFriction, defaultCutoff, instabilityThreshold = 0, shearRate = 0, defaultWeightExponent = 2;
    double defaultTransverseFriction = 0, defaultTransverseWeightExponent = 2;
    std::map<int, double> typePairWeightExponent;  // by type-pair index, where set
    std::map<int, std::pair<double, double>> typePairTransverse;  // (friction, exponent) by type-pair index, where set
    struct Exception {
        int particle1, particle2;
        double factor;
    };
    std::vector<Exception> exceptions;
    std::map<std::pair<int, int>, int> exceptionIndex;  // by (lower, higher) particle index
    bool pressureTensorEnabled = false;
    int randomNumberSeed, parametersVersion = 0, seedVersion = 0;
    ParticleTypeTable types;
    OpenMM::Kernel kernel;
};

} // namespace DPDPlugin

#endif
