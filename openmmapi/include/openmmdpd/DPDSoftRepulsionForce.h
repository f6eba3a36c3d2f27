#ifndef OPENMMDPD_DPDSOFTREPULSIONFORCE_H_
#define OPENMMDPD_DPDSOFTREPULSIONFORCE_H_

#include "openmmdpd/ParticleTypeTable.h"
#include "openmm/Context.h"
#include "openmm/Force.h"
#include <map>
#include <utility>
#include <vector>

namespace DPDPlugin {

/**
 * The soft repulsion of DPD, the conservative force nearly every DPD system has:
 *
 *     E = a_ij rc_ij (1 - r/rc_ij)^2 / 2,   F = a_ij (1 - r/rc_ij) e   for r < rc_ij
 *
 * with a_ij (kJ/mol/nm) and rc_ij (nm) per pair of particle types, like the integrators'
 * type-pair table: pairs of types without an entry use the defaults.  Particle types are
 * integers >= 0 (0 unless set).  Excluded pairs (e.g. bonded ones) do not interact.
 * Periodic (CutoffPeriodic, the default) or not (CutoffNonPeriodic).
 */
class DPDSoftRepulsionForce : public OpenMM::Force {
public:
    enum NonbondedMethod {
        CutoffNonPeriodic = 1,
        CutoffPeriodic = 2
    };
    /**
     * @param defaultA       the repulsion parameter a of pairs without a type-pair entry (kJ/mol/nm), >= 0
     * @param defaultCutoff  the cutoff rc of pairs without a type-pair entry (nm), > 0
     */
    DPDSoftRepulsionForce(double defaultA, double defaultCutoff);
    double getDefaultA() const { return defaultA; }
    void setDefaultA(double a);
    double getDefaultCutoff() const { return defaultCutoff; }
    void setDefaultCutoff(double cutoff);
    NonbondedMethod getNonbondedMethod() const { return method; }
    void setNonbondedMethod(NonbondedMethod method);
    int getParticleType(int index) const { return types.getParticleType(index); }
    void setParticleType(int index, int type) { types.setParticleType(index, type); }
    const std::map<int, int>& getParticleTypes() const { return types.getParticleTypes(); }
    /** Parameters for pairs of types type1 and type2 (either order): a in kJ/mol/nm, cutoff in nm. */
    int addTypePair(int type1, int type2, double a, double cutoff) { return types.addTypePair(type1, type2, a, cutoff); }
    int getNumTypePairs() const { return types.getNumTypePairs(); }
    void getTypePairParameters(int pairIndex, int& type1, int& type2, double& a, double& cutoff) const;
    void setTypePairParameters(int pairIndex, int type1, int type2, double a, double cutoff) {
        types.setTypePair(pairIndex, type1, type2, a, cutoff);
    }
    /** Exclude a pair of particles from the interaction; returns the exclusion's index. */
    int addExclusion(int particle1, int particle2);
    int getNumExclusions() const { return (int) exclusions.size(); }
    void getExclusionParticles(int index, int& particle1, int& particle2) const;
    /** The largest cutoff over the default and all type pairs (nm). */
    double getMaxCutoff() const { return types.getMaxCutoff(defaultCutoff); }
    /** The types and type pairs, with their checks. */
    const ParticleTypeTable& getTypeTable() const { return types; }
    bool usesPeriodicBoundaryConditions() const override { return method == CutoffPeriodic; }
    /**
     * Copy a, cutoffs, types and type pairs into a Context that uses this force (the set of
     * exclusions and the nonbonded method cannot change).
     */
    void updateParametersInContext(OpenMM::Context& context);

protected:
    OpenMM::ForceImpl* createImpl() const override;

private:
    double defaultA, defaultCutoff;
    NonbondedMethod method;
    ParticleTypeTable types;
    std::vector<std::pair<int, int>> exclusions;
};

} // namespace DPDPlugin

#endif
