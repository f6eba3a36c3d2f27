#ifndef OPENMMDPD_STAGGEREDSTEPS_H_
#define OPENMMDPD_STAGGEREDSTEPS_H_

#include "openmmdpd/StaggeredDPDIntegrator.h"
#include "openmm/OpenMMException.h"

namespace DPDPlugin {

/**
 * The slow force at the two ends of sub-step s of K (docs/theory/staggered.md), as weights of
 * F (the step before's) and F^ (this step's): Fold = oldOfF F + oldOfNewF F^, Fnew = newOfF F +
 * newOfNewF F^; linear in time from F to F^ (weighted), or F and F^.
 */
struct SubStepWeights {
    SubStepWeights(const StaggeredDPDIntegrator& integrator, int s) {
        const int K = integrator.getNumSubSteps();
        const bool weighted = integrator.getWeighted();
        oldOfF = weighted ? (double) (K - s) / K : 1.0;
        oldOfNewF = weighted ? (double) s / K : 0.0;
        newOfF = weighted ? (double) (K - s - 1) / K : 0.0;
        newOfNewF = weighted ? (double) (s + 1) / K : 1.0;
    }
    double oldOfF, oldOfNewF, newOfF, newOfNewF;
};

/** A step kernel is made for one base scheme: refuses the integrator's if it changed since. */
inline void requireBaseScheme(const StaggeredDPDIntegrator& integrator, StaggeredDPDIntegrator::BaseScheme base) {
    if (integrator.getBaseScheme() != base)
        throw OpenMM::OpenMMException("StaggeredDPDIntegrator: the base scheme changed after the Context was created; call "
                                      "Context.reinitialize(True) after setBaseScheme()");
}

} // namespace DPDPlugin

#endif
