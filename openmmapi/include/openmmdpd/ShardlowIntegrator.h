#ifndef OPENMMDPD_SHARDLOWINTEGRATOR_H_
#define OPENMMDPD_SHARDLOWINTEGRATOR_H_

#include "openmmdpd/DPDThermostatIntegrator.h"

namespace DPDPlugin {

/**
 * DPD by Shardlow's splitting (docs/theory/shardlow.md): the fluctuation-dissipation part
 * is solved pair by pair, sequentially (each pair sees the velocities the pairs before it
 * changed), and the conservative part by velocity Verlet.
 *
 * - order 1 (S1): pair sweep over dt, then velocity Verlet;
 * - order 2 (S2): pair sweep over dt/2, velocity Verlet, pair sweep over dt/2 in reverse
 *   order.
 *
 * The pairs are swept in an order fixed by the geometry, so runs are reproducible and do
 * not depend on the number of threads.  Friction and cutoffs are as in every
 * DPDThermostatIntegrator (gamma_ij = 2 mu_ij friction).
 */
class ShardlowIntegrator : public DPDThermostatIntegrator {
public:
    /**
     * @param temperature      the temperature of the heat bath (K)
     * @param defaultFriction  the friction rate of pairs without a type-pair entry (1/ps)
     * @param defaultCutoff    the thermostat cutoff of pairs without a type-pair entry (nm)
     * @param stepSize         the step size (ps)
     */
    ShardlowIntegrator(double temperature, double defaultFriction, double defaultCutoff, double stepSize);
    /** Get the splitting order: 1 (S1) or 2 (S2). */
    int getOrder() const { return order; }
    /** Set the splitting order: 1 (S1, the default) or 2 (S2). */
    void setOrder(int order);

protected:
    /** S1 and S2 sweep transverse friction as they sweep the friction along e, in a System without constraints. */
    void validateTransverseFriction(const OpenMM::System& system) const override { refuseTransverseFrictionWithConstraints(system); }
    std::string kernelName() const override;
    void initializeStepKernel(OpenMM::Kernel& kernel, const OpenMM::System& system) const override;
    void executeStepKernel(OpenMM::Kernel& kernel, OpenMM::ContextImpl& context) const override;

private:
    int order;
};

} // namespace DPDPlugin

#endif
