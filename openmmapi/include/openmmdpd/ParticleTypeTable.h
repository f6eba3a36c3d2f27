#ifndef OPENMMDPD_PARTICLETYPETABLE_H_
#define OPENMMDPD_PARTICLETYPETABLE_H_

#include "openmm/System.h"
#include <map>
#include <string>
#include <vector>

namespace DPDPlugin {

/**
 * Particle types and a per-type-pair (value, cutoff) table, with the checks every user of
 * it needs: the thermostats (value = friction, 1/ps) and DPDSoftRepulsionForce (value = a,
 * kJ/mol/nm) hold one each, so types mean the same in both.  Types are integers >= 0; a
 * particle is of type 0 unless set.  Errors are OpenMMExceptions naming the parameter.
 */
class ParticleTypeTable {
public:
    struct TypePair {
        int type1, type2;
        double value, cutoff;
    };
    /**
     * @param owner      the class name that error messages start with, e.g. "DPDVVIntegrator"
     * @param valueName  the parameter's name in error messages, e.g. "friction"
     * @param valueUnit  its unit in error messages, e.g. "/ps"
     * @param signedValues  whether values may be negative (an attraction), not only >= 0
     */
    ParticleTypeTable(const std::string& owner, const std::string& valueName, const std::string& valueUnit, bool signedValues = false) :
            owner(owner), valueName(valueName), valueUnit(valueUnit), signedValues(signedValues) {}
    int getParticleType(int index) const;
    void setParticleType(int index, int type);
    /** Every particle type that was set explicitly, by particle index. */
    const std::map<int, int>& getParticleTypes() const { return particleType; }
    int addTypePair(int type1, int type2, double value, double cutoff);
    int getNumTypePairs() const { return (int) typePairs.size(); }
    const TypePair& getTypePair(int pairIndex) const;
    void setTypePair(int pairIndex, int type1, int type2, double value, double cutoff);
    /** The largest cutoff (value) over a default and all type pairs. */
    double getMaxCutoff(double defaultCutoff) const;
    double getMaxValue(double defaultValue) const;
    /** Throw unless every particle index exists in the System and every type pair names a type in use. */
    void validate(const OpenMM::System& system) const;

private:
    void checkTypePair(int type1, int type2, double value, double cutoff, int replacing) const;
    void checkPairIndex(int pairIndex) const;
    std::string owner, valueName, valueUnit;
    bool signedValues;
    std::map<int, int> particleType;
    std::vector<TypePair> typePairs;
};

} // namespace DPDPlugin

#endif
