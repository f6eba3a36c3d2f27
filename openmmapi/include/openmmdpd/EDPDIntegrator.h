#ifndef OPENMMDPD_EDPDINTEGRATOR_H_
#define OPENMMDPD_EDPDINTEGRATOR_H_

#include "openmmdpd/DPDThermostatIntegrator.h"

namespace DPDPlugin {

/**
 * Extended dissipative particle dynamics (Cotter and Reich 2003; docs/theory/edpd.md): each
 * pair k = (i, j) carries an auxiliary force s_k, an Ornstein-Uhlenbeck process driven by
 * the pair's motion, that replaces the dissipative and random forces of DPD:
 *
 *     dp_i = [F_i - sum_j wR(r_ij) e_ij s_ij] dt
 *     ds_k = -[alpha s_k - lambda_k dh_k/dt] dt + sqrt(2 kT lambda_k alpha) dW_k
 *
 * with h_k = phi(r_ij), phi' = wR.  The noise thus has a memory time 1/alpha; standard DPD
 * with friction gamma is the limit alpha -> infinity at lambda = alpha gamma.
 *
 * Parameters: the coupling is given the way the other integrators give friction, so that
 * one type-pair table serves all of them: a pair with friction rate f (1/ps) has
 * gamma_ij = 2 mu_ij f (amu/ps, = f for unit masses) and lambda_ij = alpha gamma_ij
 * (kJ/mol/nm^2).  Holding the friction fixed while raising alpha therefore approaches the
 * DPD fluid that DPDVVIntegrator simulates with the same friction.
 *
 * Schemes (one force evaluation per step each):
 * - OneSided (default): Störmer-Verlet with the implicit one-sided s update,
 *   (1 + alpha dt) s' = s + lambda dh + sqrt(2 kT lambda alpha dt) w.  Stable at any
 *   alpha dt, so it also covers the DPD limit; the stationary variance of s is
 *   kT lambda / (1 + alpha dt / 2).
 * - Symmetric: (1 + alpha dt/2) s' = (1 - alpha dt/2) s + lambda dh + ...; keeps the
 *   exact variance kT lambda and is the more accurate for alpha dt << 1, but it is
 *   unstable for alpha dt >> 1.
 *
 * The s_k are state: a pair's s is created from its stationary law when the pair first
 * comes within its cutoff, carried while it is out of range (there h is constant, and the
 * recurrence is solved in closed form over the steps it was away), forgotten once its
 * memory |rho|^steps has decayed below 1e-8, and saved in checkpoints.
 */
class EDPDIntegrator : public DPDThermostatIntegrator {
public:
    enum Scheme {
        OneSided = 0,
        Symmetric = 1
    };
    /**
     * @param temperature      the temperature of the heat bath (K)
     * @param defaultFriction  the friction rate of pairs without a type-pair entry (1/ps);
     *                         lambda = alpha * 2 mu friction
     * @param defaultCutoff    the cutoff of pairs without a type-pair entry (nm)
     * @param alpha            the decay rate of the auxiliary variables (1/ps), > 0
     * @param stepSize         the step size (ps)
     */
    EDPDIntegrator(double temperature, double defaultFriction, double defaultCutoff, double alpha, double stepSize);
    /** Get the decay rate alpha of the auxiliary variables (1/ps). */
    double getAlpha() const { return alpha; }
    /** Set the decay rate alpha of the auxiliary variables (1/ps), > 0. */
    void setAlpha(double alpha);
    Scheme getScheme() const { return scheme; }
    void setScheme(Scheme s);
    /**
     * The auxiliary variable s of the pair (i, j) (kJ/mol/nm) as of the last step in which
     * it was updated (the current step for pairs within their cutoff; a pair out of range
     * is brought up to date only when it returns), or NaN if the pair is not remembered.
     * Requires a Context.
     */
    double getPairVariable(int particle1, int particle2) const;
    /** The step whose value getPairVariable() returns for this pair (-1 if none). */
    long long getPairVariableStep(int particle1, int particle2) const;
    /** How many pair variables the Context holds now, within range and remembered. */
    long long getNumPairVariables() const;
    /** As DPDThermostatIntegrator's, and the weights must be standard (exponent 2): EDPD's pair coupling is built on w = 1 - r/rc. */
    void validate(const OpenMM::System& system) const override;

protected:
    std::string kernelName() const override;
    void initializeStepKernel(OpenMM::Kernel& kernel, const OpenMM::System& system) const override;
    void executeStepKernel(OpenMM::Kernel& kernel, OpenMM::ContextImpl& context) const override;

private:
    double alpha;
    Scheme scheme;
};

} // namespace DPDPlugin

#endif
