#ifndef OPENMMDPD_DPDVVINTEGRATOR_H_
#define OPENMMDPD_DPDVVINTEGRATOR_H_

#include "openmmdpd/DPDThermostatIntegrator.h"

namespace DPDPlugin {

/**
 * Dissipative particle dynamics with the velocity-Verlet family of integrators
 * (docs/theory/velocity-verlet.md):
 *
 * - GrootWarren: positions by velocity Verlet, the dissipative force evaluated at the
 *   predicted velocity v + lambda dt F/m.  lambda = 0.5 (the default) is plain velocity
 *   Verlet (what LAMMPS' pair dpd + fix nve does); 0.65 is Groot and Warren's choice.
 * - DPDVV: Besold et al.'s DPD-VV: the dissipative force is recomputed with the new
 *   velocity at the end of the step.
 * - SelfConsistent: SC-VV, DPD-VV whose last half kick and dissipative force are iterated
 *   until the instantaneous temperature changes by less than the tolerance (relative), or
 *   for at most maxIterations iterations.
 *
 * Conservative forces come from the System's Forces (the integration force groups); the
 * dissipative and random pair forces come from this integrator's type-pair table.
 */
class DPDVVIntegrator : public DPDThermostatIntegrator {
public:
    enum Variant {
        GrootWarren = 0,
        DPDVV = 1,
        SelfConsistent = 2
    };
    /**
     * @param temperature      the temperature of the heat bath (K)
     * @param defaultFriction  the friction rate of pairs without a type-pair entry (1/ps)
     * @param defaultCutoff    the thermostat cutoff of pairs without a type-pair entry (nm)
     * @param stepSize         the step size (ps)
     */
    DPDVVIntegrator(double temperature, double defaultFriction, double defaultCutoff, double stepSize);
    Variant getVariant() const { return variant; }
    void setVariant(Variant v);
    /** Get the velocity-prediction parameter of the GrootWarren variant (dimensionless). */
    double getLambda() const { return lambda; }
    /** Set the velocity-prediction parameter of the GrootWarren variant, in [0, 1]. */
    void setLambda(double lambda);
    /** Get the iteration cap of the SelfConsistent variant. */
    int getMaxIterations() const { return maxIterations; }
    /** The largest iteration cap: each iteration is a pass over the pairs, so more would only look like a hang. */
    static constexpr int MAX_ITERATIONS = 1000;
    /** Set the iteration cap of the SelfConsistent variant, from 1 to MAX_ITERATIONS. */
    void setMaxIterations(int iterations);
    /** Get the relative temperature tolerance that ends the SelfConsistent iteration. */
    double getTolerance() const { return tolerance; }
    /** Set the relative temperature tolerance of the SelfConsistent variant (>= 0). */
    void setTolerance(double tol);

protected:
    /** Every variant has transverse friction, with or without constraints. */
    void validateTransverseFriction(const OpenMM::System&) const override {}
    std::string kernelName() const override;
    void initializeStepKernel(OpenMM::Kernel& kernel, const OpenMM::System& system) const override;
    void executeStepKernel(OpenMM::Kernel& kernel, OpenMM::ContextImpl& context) const override;

private:
    Variant variant;
    double lambda, tolerance;
    int maxIterations;
};

} // namespace DPDPlugin

#endif
