#ifndef OPENMMDPD_DPDPAIRROWS_H_
#define OPENMMDPD_DPDPAIRROWS_H_

#include "openmmdpd/DPDThermostatForces.h"

namespace DPDPlugin {

/** A thermostat batch's pairs, as DPDSlotForces holds them: pair k joins slots slotP[k] and slotQ[k]. */
struct DPDBatchPairs {
    const PairGeometry* geometry;
    const int* slotP;
    const int* slotQ;
    const double* xi;          // each pair's normal number
    const double* softAlongE;  // each pair's soft force along e (null: no soft force)
    bool sheared;              // whether the pairs' imageVx are to be read (else all 0)
    DPDThermostatForces::KeptPair* kept;  // where each pair's slots, e and gammaWD are copied (null: nowhere)
};

/**
 * FR + FD of the batch's pairs (DPDPairForce, with the velocities of their slots) and the
 * soft force along e, four pairs at a time where the processor has AVX2: to forces[k] as
 * (FD + FR) + soft, or, given dissipative, FD to dissipative[k] and FR + soft to forces[k];
 * and pair k to kept[k] if asked (not its imageVx).  The copies are made among the
 * arithmetic: a loop of copies alone waits on its stores.
 * Bit for bit what DPDPairForce gives pair by pair (the same operations in the same order
 * in each lane, no FMA).  Makes pairs [0, m) for the m it returns (n rounded down to a
 * multiple of four; 0 without AVX2): the caller makes the rest.
 */
int dpdPairForceRows(const DPDBatchPairs& pairs, int n, const OpenMM::Vec3* velocities, double invSqrtDt, OpenMM::Vec3* forces,
                     OpenMM::Vec3* dissipative);

/**
 * FD of kept pairs [0, n) (a FindAndKeepPairs pass's; with the velocities of their slots,
 * j moving with imageVx[k] unless null) to forces[k], four pairs at a time where the
 * processor has AVX2, bit for bit DPDPairForce::dissipative.  Returns m as above.
 */
int dpdKeptDissipativeRows(const DPDThermostatForces::KeptPair* kept, const double* imageVx, int n, const OpenMM::Vec3* velocities,
                           OpenMM::Vec3* forces);

} // namespace DPDPlugin

#endif
