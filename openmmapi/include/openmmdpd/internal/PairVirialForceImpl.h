#ifndef OPENMMDPD_PAIRVIRIALFORCEIMPL_H_
#define OPENMMDPD_PAIRVIRIALFORCEIMPL_H_

#include "openmm/internal/ForceImpl.h"
#include <array>

namespace DPDPlugin {

/**
 * A force of central pair forces whose energy depends on the pair distances alone, so its
 * virial sum_pairs r_ij,a F_ij,b is exact: the pressure tensor (PressureTensorSampler) takes
 * that sum from it and leaves it out while it strains the other forces of its group.
 */
class PairVirialForceImpl : public OpenMM::ForceImpl {
public:
    /** The pair virial at the Context's positions (kJ/mol) as (xx, yy, zz, xy, xz, yz). */
    virtual std::array<double, 6> computeVirial(OpenMM::ContextImpl& context) = 0;
    /** While left out, the force adds no force or energy. */
    void setLeftOut(bool out) { leftOut = out; }

protected:
    bool isLeftOut() const { return leftOut; }

private:
    bool leftOut = false;
};

} // namespace DPDPlugin

#endif
