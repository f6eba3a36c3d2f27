#ifndef OPENMMDPD_MDPDPARAMETERS_H_
#define OPENMMDPD_MDPDPARAMETERS_H_

#include "openmmdpd/MDPDForce.h"
#include "openmmdpd/PairParameters.h"
#include <vector>

namespace DPDPlugin {

/**
 * An MDPDForce resolved for the kernels (docs/theory/mdpd.md): A and rc per type pair in a
 * TypePairTable, B per (dense) particle type, the density range rd and the normalisations of
 * Warren 2003's density weight and energy.  The host platforms' pair terms are here.
 */
class MDPDParameters {
public:
    MDPDParameters(int numParticles, const MDPDForce& force);
    const TypePairTable& getTable() const { return table; }
    /** B of a dense particle type (kJ/mol/nm). */
    double typeB(int denseType) const { return bOfType[denseType]; }
    const std::vector<double>& getTypeBs() const { return bOfType; }
    double getDensityCutoff() const { return densityCutoff; }
    double getInverseDensityCutoff() const { return inverseDensityCutoff; }
    /** 15/(2 pi rd^3): the density weight's normalisation (its integral over space is 1). */
    double getDensityNorm() const { return densityNorm; }
    /** pi rd^4 / 30: a particle's energy is this B rho^2. */
    double getEnergyFactor() const { return energyFactor; }
    /** The density weight of a pair at distance r (0 beyond rd). */
    double densityWeight(double r) const {
        return r < densityCutoff ? mdpdDensityWeight(r, densityNorm, inverseDensityCutoff) : 0.0;
    }
    /** The force on i along e of a pair of type pair t at r < rc, given B_i rho_i + B_j rho_j (kJ/mol/nm). */
    double pairForce(int t, double r, double densityRepulsion) const {
        // The repulsion times 1 or 0 (the sum, or exactly the attraction): a branch on r < rd
        // would be mispredicted often.
        const double attraction = softRepulsionAlongE(r, table.value(t), table.inverseCutoff(t));
        const double inRange = (r < densityCutoff ? 1.0 : 0.0);
        return attraction + inRange * mdpdRepulsionAlongE(r, densityRepulsion, inverseDensityCutoff);
    }
    /** The energy of the A term of a pair of type pair t at r < rc (kJ/mol). */
    double pairEnergy(int t, double r) const { return softRepulsionEnergy(r, table.value(t), table.cutoff(t)); }
    /** The density term's energy of a particle of dense type `type` at local density rho (kJ/mol). */
    double particleEnergy(int type, double rho) const { return mdpdDensityEnergy(rho, bOfType[type], energyFactor); }

private:
    TypePairTable table;
    std::vector<double> bOfType;
    double densityCutoff, inverseDensityCutoff, densityNorm, energyFactor;
};

} // namespace DPDPlugin

#endif
