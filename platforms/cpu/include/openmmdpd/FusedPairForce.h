#ifndef OPENMMDPD_FUSEDPAIRFORCE_H_
#define OPENMMDPD_FUSEDPAIRFORCE_H_

#include "openmmdpd/PairParameters.h"

namespace OpenMM {
class ContextImpl;
}

namespace DPDPlugin {

/**
 * A conservative pair force that an integrator's thermostat pass adds for the pairs it
 * visits, so that they are searched once per step, not twice: DPDSoftRepulsionForce, and
 * MDPDForce once its local densities are summed.  While deferred, the force's own
 * execute() adds no force (MDPDForce's still sums the densities the pass then reads).
 */
class FusedPairForce {
public:
    virtual ~FusedPairForce() = default;
    virtual void setDeferred(bool value) = 0;
    /** Make pairForces() hold at the Context's positions where execute() is not called. */
    virtual void prepare(OpenMM::ContextImpl& context) = 0;
    /** Changes whenever the parameters do (for callers that cache checks on them). */
    virtual int getParametersVersion() const = 0;
    /** The force's types and cutoffs (and its pair values a or A). */
    virtual const TypePairTable& getTable() const = 0;
    virtual bool isPeriodic() const = 0;
    /**
     * Whether every pair's force is the soft repulsion of the table's one entry (one type,
     * no exclusions): then the thermostat's vector rows make it.
     */
    virtual bool isUniformSoftRepulsion() const = 0;
    /**
     * A value per particle (by particle index) that pairForces() reads summed over each
     * pair (MDPDForce's B rho), valid from prepare() or a deferred execute() to the next;
     * null where it reads none.
     */
    virtual const double* getParticleValues() const = 0;
    /**
     * out[k] = the force on particle first[k] along e = (r_i - r_j)/r of its pair with
     * second[k] at distance r[k], of table index types[k] (0 beyond the cutoff or excluded),
     * for k < n; valueSums[k] = the sum of the pair's getParticleValues() (null where those are).
     */
    virtual void pairForces(int n, const int* first, const int* second, const int* types, const double* r,
                            const double* valueSums, double* out) const = 0;
};

} // namespace DPDPlugin

#endif
