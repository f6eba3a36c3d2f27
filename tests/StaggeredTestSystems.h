#ifndef OPENMMDPD_STAGGEREDTESTSYSTEMS_H_
#define OPENMMDPD_STAGGEREDTESTSYSTEMS_H_

// The polymer part of the staggered integrator's test systems.

#include "openmm/CustomBondForce.h"
#include "openmm/CustomNonbondedForce.h"
#include "openmm/System.h"
#include <set>

/**
 * Makes particles 0 .. chains * beads - 1 into `chains` chains of `beads` consecutive particles:
 * neighbours bonded by `fene` and excluded from `wca`, whose one interaction group is all the
 * beads.  Both go into force group 1 (the staggered integrator's fast group) and are added to
 * `system`, fene first.
 */
inline void addChainForces(OpenMM::System& system, OpenMM::CustomBondForce* fene, OpenMM::CustomNonbondedForce* wca,
                           int chains, int beads) {
    std::set<int> members;
    for (int i = 0; i < chains * beads; i++) {
        members.insert(i);
        if (i % beads != 0) {
            fene->addBond(i - 1, i, {});
            wca->addExclusion(i - 1, i);
        }
    }
    wca->addInteractionGroup(members, members);
    fene->setForceGroup(1);
    wca->setForceGroup(1);
    system.addForce(fene);
    system.addForce(wca);
}

#endif
