#ifndef OPENMMDPD_FORCETERMS_H_
#define OPENMMDPD_FORCETERMS_H_

#include "openmm/Force.h"
#include "openmm/System.h"
#include <functional>
#include <vector>

/*
 * What the System's Forces say about which particles act together, for the integrators'
 * checks and for the parts of a step that move molecules as a whole: every question of that
 * kind goes through the terms listed here.
 */

namespace DPDPlugin {

/** One term of a force: its class, what the class calls its terms, the index, the particles. */
struct Term {
    const char* forceClass;
    const char* kind;
    int index;
    std::vector<int> particles;
};

using TermVisitor = std::function<void(const Term&)>;

/**
 * Calls `visit` for every term of `force` with the particles it acts on; returns false, having
 * visited nothing, if the force does not list them (a NonbondedForce, a CustomNonbondedForce
 * without interaction groups, a CustomManyParticleForce or GB force: all particles, each
 * switched on or off by its parameters; a force of a kind this does not know).
 */
bool forEachTerm(const OpenMM::Force& force, const TermVisitor& visit);

/**
 * Whether `force` is a bonded force: its terms join particles into molecules (bonds, angles,
 * torsions, CMAP, custom bond, angle, torsion, compound and centroid bonds).
 */
bool isBondedForce(const OpenMM::Force& force);

/**
 * The molecules of a System: particles joined, directly or through others, by a term of a
 * bonded force, a constraint or a virtual site's definition.  Every particle is in exactly
 * one molecule; each molecule lists its particles in increasing order, and the molecules are
 * ordered by their first particle.
 */
std::vector<std::vector<int>> findMolecules(const OpenMM::System& system);

} // namespace DPDPlugin

#endif
