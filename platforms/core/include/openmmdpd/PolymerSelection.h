#ifndef OPENMMDPD_POLYMERSELECTION_H_
#define OPENMMDPD_POLYMERSELECTION_H_

#include "openmmdpd/StaggeredDPDIntegrator.h"
#include "openmm/System.h"
#include <vector>

namespace DPDPlugin {

/**
 * The polymer particles a staggered step kernel sub-cycles, for the integrator's fast force
 * groups and explicit list as they were when selected, on every platform.
 */
class PolymerSelection {
public:
    /** Select for the integrator's current settings (raises if the explicit list misses a particle). */
    void select(const OpenMM::System& system, const StaggeredDPDIntegrator& integrator) {
        particles = integrator.findPolymerParticles(system);
        groups = integrator.getFastForceGroups();
        explicitList = integrator.getPolymerParticles();
        checkFastForceOutside = !integrator.fastForcesListTheirParticles(system);
        index.assign(system.getNumParticles(), -1);
        for (size_t k = 0; k < particles.size(); k++)
            index[particles[k]] = (int) k;
    }
    /** Whether the integrator's fast groups or explicit list changed since select(). */
    bool changed(const StaggeredDPDIntegrator& integrator) const {
        return integrator.getFastForceGroups() != groups || integrator.getPolymerParticles() != explicitList;
    }
    std::vector<int> particles;  // increasing
    std::vector<int> index;      // k with particles[k] = i, or -1, by particle i
    // A fast force lists no particles, so the explicit list could not be checked against it
    // when selected: the fast forces must then leave every other particle alone at every step.
    bool checkFastForceOutside = false;

private:
    int groups = 0;
    std::vector<int> explicitList;
};

} // namespace DPDPlugin

#endif
