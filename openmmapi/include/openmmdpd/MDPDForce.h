#ifndef OPENMMDPD_MDPDFORCE_H_
#define OPENMMDPD_MDPDFORCE_H_

#include "openmmdpd/ParticleTypeTable.h"
#include "openmm/Context.h"
#include "openmm/Force.h"
#include <map>
#include <utility>
#include <vector>

namespace DPDPlugin {

/**
 * Many-body DPD (docs/theory/mdpd.md): an attraction A w_c on the cutoff rc plus a repulsion
 * that grows with the local densities on the shorter range rd,
 *
 *     F_ij = [A_ij (1 - r/rc_ij) + (B_i rho_i + B_j rho_j) (1 - r/rd)] e,
 *     rho_i = sum_j 15/(2 pi rd^3) (1 - r_ij/rd)^2      (Warren 2003's normalisation),
 *
 * the gradient of the energy
 *
 *     E = sum_pairs A_ij rc_ij (1 - r/rc_ij)^2 / 2 + sum_i pi rd^4 B_i rho_i^2 / 30.
 *
 * A (kJ/mol/nm, usually < 0: the attraction) and rc (nm) are set per pair of particle types,
 * with defaults for pairs without an entry.  B (kJ/mol/nm, >= 0) is set per particle type
 * and rd (nm, at most every rc) is one for the force: with B or rd per pair the force is the
 * gradient of no energy (Warren 2013).  Excluded pairs neither interact nor count in each
 * other's density.  Periodic (CutoffPeriodic, the default) or not (CutoffNonPeriodic).
 */
class MDPDForce : public OpenMM::Force {
public:
    enum NonbondedMethod {
        CutoffNonPeriodic = 1,
        CutoffPeriodic = 2
    };
    /**
     * @param defaultA        the attraction parameter A of pairs without a type-pair entry (kJ/mol/nm), any finite value
     * @param defaultB        the density repulsion B of particle types without their own (kJ/mol/nm), >= 0
     * @param defaultCutoff   the cutoff rc of pairs without a type-pair entry (nm), > 0
     * @param densityCutoff   the range rd of the density and of the repulsion (nm), in (0, every rc]
     */
    MDPDForce(double defaultA, double defaultB, double defaultCutoff, double densityCutoff);
    double getDefaultA() const { return defaultA; }
    void setDefaultA(double a);
    double getDefaultB() const { return defaultB; }
    void setDefaultB(double b);
    double getDefaultCutoff() const { return defaultCutoff; }
    void setDefaultCutoff(double cutoff);
    double getDensityCutoff() const { return densityCutoff; }
    void setDensityCutoff(double cutoff);
    NonbondedMethod getNonbondedMethod() const { return method; }
    void setNonbondedMethod(NonbondedMethod method);
    int getParticleType(int index) const { return types.getParticleType(index); }
    void setParticleType(int index, int type) { types.setParticleType(index, type); }
    const std::map<int, int>& getParticleTypes() const { return types.getParticleTypes(); }
    /** A (kJ/mol/nm) and the cutoff rc (nm, >= the density cutoff) for pairs of types type1 and type2 (either order). */
    int addTypePair(int type1, int type2, double a, double cutoff);
    int getNumTypePairs() const { return types.getNumTypePairs(); }
    void getTypePairParameters(int pairIndex, int& type1, int& type2, double& a, double& cutoff) const;
    void setTypePairParameters(int pairIndex, int type1, int type2, double a, double cutoff);
    /** B (kJ/mol/nm, >= 0) of the particles of one type. */
    void setTypeB(int type, double b);
    /** B of a type: its own if set, else the default. */
    double getTypeB(int type) const;
    /** The types with their own B. */
    const std::map<int, double>& getTypeBs() const { return typeB; }
    /** Exclude a pair of particles from the interaction and from each other's density; returns the exclusion's index. */
    int addExclusion(int particle1, int particle2);
    int getNumExclusions() const { return (int) exclusions.size(); }
    void getExclusionParticles(int index, int& particle1, int& particle2) const;
    /** The largest cutoff over the default and all type pairs (nm). */
    double getMaxCutoff() const { return types.getMaxCutoff(defaultCutoff); }
    /** The smallest cutoff over the default and all type pairs (nm). */
    double getMinCutoff() const;
    /** The types and type pairs, with their checks. */
    const ParticleTypeTable& getTypeTable() const { return types; }
    bool usesPeriodicBoundaryConditions() const override { return method == CutoffPeriodic; }
    /**
     * Copy A, B, the cutoffs, types and type pairs into a Context that uses this force (the
     * set of exclusions and the nonbonded method cannot change).
     */
    void updateParametersInContext(OpenMM::Context& context);

protected:
    OpenMM::ForceImpl* createImpl() const override;

private:
    void checkPairCutoff(double cutoff) const;
    double defaultA, defaultB, defaultCutoff, densityCutoff;
    NonbondedMethod method;
    ParticleTypeTable types;
    std::map<int, double> typeB;
    std::vector<std::pair<int, int>> exclusions;
};

} // namespace DPDPlugin

#endif
