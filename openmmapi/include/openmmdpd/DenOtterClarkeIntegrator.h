#ifndef OPENMMDPD_DENOTTERCLARKEINTEGRATOR_H_
#define OPENMMDPD_DENOTTERCLARKEINTEGRATOR_H_

#include "openmmdpd/DPDThermostatIntegrator.h"

namespace DPDPlugin {

/**
 * den Otter and Clarke's leap-frog (OC; docs/theory/den-otter-clarke.md, Nikunen et al.
 * 2003, Table II and eqs. 6-7), with two prefactors fitted to the system:
 *
 *     v <- v + alpha dt/m (FC + FD) + beta dt/m FR        (FR with its 1/sqrt(dt))
 *     r <- r + dt v
 *
 * FC, FD(v) and FR are evaluated at the start of each step, at the positions and with the
 * velocities the kick acts on: the same sequence as Table II, whose step (3) computes them
 * at the end of the step before.  The velocities are leap-frog half-step velocities, and
 * the kinetic energy is theirs (as in the paper, which measures <kT> from them).
 *
 *     alpha  = (1 - exp(-G dt)) / (G dt),   G = -<FD_i . v_i> / (m <v_i . v_i>) = -<FD_i . v_i> / (3 kT)
 *     beta^2 = (-2 m alpha <FD_i . v_i> - alpha^2 dt <FD_i . FD_i>) / <FR_i . FR_i>
 *
 * with the averages per particle (over particles and time) of an equilibrium ensemble at the
 * target temperature, FR_i here without the 1/sqrt(dt).  Interpretation: the paper writes
 * G = -<FD.v>/<v.v> in reduced units with m = 1; a rate needs the mass, and <v.v> = 3 kT/m at
 * equilibrium, so G = -<FD.v>/(3 kT), the paper's value for m = kT = 1.  beta is what keeps
 * <v.v> stationary: |v + alpha dt FD/m + beta sqrt(dt) FR/m|^2 averages to |v|^2.
 *
 * The averages are given with setAverageFDDotV(), setAverageFDDotFD() and
 * setAverageFRDotFR() (Nikunen et al. 2003, Table III, has them for its models), or measured on the
 * System in a short run at a small step (openmmdpd.calibrate_den_otter_clarke, which uses
 * getMeasuredSums()).  They belong to the temperature, friction, cutoffs and density they were
 * measured at: measure them again after changing any of these.  The prefactors are one pair
 * for all particles (Nikunen et al. 2003, §II.C), so every particle with mass must have the
 * same mass.
 */
class DenOtterClarkeIntegrator : public DPDThermostatIntegrator {
public:
    /**
     * The averages are not set (0): set them, or measure them, before a Context is created.
     *
     * @param temperature      the temperature of the heat bath (K), > 0
     * @param defaultFriction  the friction rate of pairs without a type-pair entry (1/ps)
     * @param defaultCutoff    the thermostat cutoff of pairs without a type-pair entry (nm)
     * @param stepSize         the step size (ps)
     */
    DenOtterClarkeIntegrator(double temperature, double defaultFriction, double defaultCutoff, double stepSize);
    /** Get <FD_i . v_i> (kJ/mol/ps); 0 if not set. */
    double getAverageFDDotV() const { return fdDotV; }
    /** Set <FD_i . v_i> (kJ/mol/ps), < 0 (friction takes energy out). */
    void setAverageFDDotV(double value);
    /** Get <FD_i . FD_i> ((kJ/mol/nm)^2); 0 if not set. */
    double getAverageFDDotFD() const { return fdDotFD; }
    /** Set <FD_i . FD_i> ((kJ/mol/nm)^2), > 0. */
    void setAverageFDDotFD(double value);
    /** Get <FR_i . FR_i> with FR without 1/sqrt(dt) ((kJ/mol/nm)^2 ps); 0 if not set. */
    double getAverageFRDotFR() const { return frDotFR; }
    /** Set <FR_i . FR_i> with FR without 1/sqrt(dt) ((kJ/mol/nm)^2 ps), > 0. */
    void setAverageFRDotFR(double value);
    /**
     * alpha and beta (eqs. 6-7) for particles of mass m (amu) at the current step size and
     * temperature; throws if the averages are not set or beta^2 <= 0 (the step is too long
     * for the averages: alpha dt <FD.FD> >= -2 m <FD.v>).
     */
    void getPrefactors(double mass, double& alpha, double& beta) const;
    /**
     * What this integrator's Context measured, for calibration: sums over every step taken
     * in it and over the particles with mass of FD_i . v_i (kJ/mol/ps), FD_i . FD_i
     * ((kJ/mol/nm)^2) and FR_i . FR_i (FR without 1/sqrt(dt), (kJ/mol/nm)^2 ps), each as the
     * step evaluates it (FD with the velocities the kick acts on), and the number of terms
     * in each.  The differences of two calls, divided by the difference of the counts, are
     * the averages over the steps in between.  Throws unless bound to a Context.
     */
    void getMeasuredSums(double& sumFDDotV, double& sumFDDotFD, double& sumFRDotFR, long long& count) const;
    /**
     * Also requires temperature > 0, the three averages set, one mass for every particle
     * with mass, and beta^2 > 0 at the current step size.
     */
    void validate(const OpenMM::System& system) const override;

protected:
    /** Its step scales FC and FD by alpha and FR by beta: the applied forces do not split into the tensor's parts. */
    bool supportsPressureTensor() const override { return false; }
    std::string kernelName() const override;
    void initializeStepKernel(OpenMM::Kernel& kernel, const OpenMM::System& system) const override;
    void executeStepKernel(OpenMM::Kernel& kernel, OpenMM::ContextImpl& context) const override;

private:
    double fdDotV = 0, fdDotFD = 0, frDotFR = 0;
};

} // namespace DPDPlugin

#endif
