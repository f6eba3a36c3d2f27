#ifndef OPENMMDPD_LOWEANDERSENINTEGRATOR_H_
#define OPENMMDPD_LOWEANDERSENINTEGRATOR_H_

#include "openmmdpd/DPDThermostatIntegrator.h"

namespace DPDPlugin {

/**
 * Pairwise thermostats with a velocity-Verlet step of the conservative forces only
 * (docs/theory/lowe-andersen.md), pair by pair in an order fixed by the geometry:
 *
 * - Lowe (default): with probability Gamma dt, a pair within its cutoff gets a new
 *   relative normal velocity drawn from the Maxwell distribution (Lowe-Andersen).  The
 *   friction parameters are then the collision rates Gamma (1/ps), and Gamma dt must be
 *   <= 1.  Gamma sets the viscosity independently of the conservative forces.
 * - PairOrnsteinUhlenbeck: every pair's relative normal velocity is advanced by the exact
 *   solution of its Ornstein-Uhlenbeck equation with the DPD friction gamma_ij wD(r)
 *   (gamma_ij = 2 mu_ij friction); this discretises the DPD equations and keeps the ideal
 *   gas exact at any dt (the family of Peters' scheme; the pair update OpenMM 8.3's
 *   DPDIntegrator applies).
 *
 * Where the thermostat O sits in the step (B: half kick, A: half drift):
 * - AfterVerlet (default): B A A B O, O over the pairs at the end-of-step positions
 *   (Nikunen et al. 2003, Table V).
 * - Middle: B A O A B (docs/theory/lowe-andersen.md), O between the half drifts over the pairs
 *   found there, as a Langevin "middle" scheme puts its friction; still one force
 *   evaluation per step.  The ideal gas stays exact at any dt.  As in OpenMM's
 *   LangevinMiddleIntegrator, the Context's velocities are those at O, half a kick from
 *   the positions' time: one full kick B B opens each step.  (The end-of-step velocities
 *   of B A O A B read a kinetic kT 3 % low at dt = 0.05 on model B; those at O do not.)
 */
class LoweAndersenIntegrator : public DPDThermostatIntegrator {
public:
    enum Method {
        Lowe = 0,
        PairOrnsteinUhlenbeck = 1
    };
    enum Splitting {
        AfterVerlet = 0,
        Middle = 1
    };
    /**
     * @param temperature    the temperature of the heat bath (K)
     * @param defaultGamma   the collision rate Gamma (Lowe) or friction (PairOrnsteinUhlenbeck)
     *                       of pairs without a type-pair entry (1/ps)
     * @param defaultCutoff  the thermostat cutoff of pairs without a type-pair entry (nm)
     * @param stepSize       the step size (ps)
     */
    LoweAndersenIntegrator(double temperature, double defaultGamma, double defaultCutoff, double stepSize);
    Method getMethod() const { return method; }
    void setMethod(Method m);
    Splitting getSplitting() const { return splitting; }
    /** Takes effect at the next step, also on a live Context. */
    void setSplitting(Splitting s);
    /** Also requires Gamma dt <= 1 for every pair with the Lowe method. */
    void validate(const OpenMM::System& system) const override;

protected:
    /** The pair Ornstein-Uhlenbeck method has transverse friction, in a System without constraints; Lowe's collisions have none. */
    void validateTransverseFriction(const OpenMM::System& system) const override;
    std::string kernelName() const override;
    void initializeStepKernel(OpenMM::Kernel& kernel, const OpenMM::System& system) const override;
    void executeStepKernel(OpenMM::Kernel& kernel, OpenMM::ContextImpl& context) const override;

private:
    Method method;
    Splitting splitting;
};

} // namespace DPDPlugin

#endif
