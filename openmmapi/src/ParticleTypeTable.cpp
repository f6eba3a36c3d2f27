#include "openmmdpd/ParticleTypeTable.h"
#include "openmmdpd/internal/ParameterChecks.h"
#include <algorithm>
#include <cmath>
#include <set>

using namespace DPDPlugin;
using OpenMM::OpenMMException;

int ParticleTypeTable::getParticleType(int index) const {
    require(index >= 0, owner + ": particle index must be >= 0, got " + std::to_string(index));
    auto it = particleType.find(index);
    return it == particleType.end() ? 0 : it->second;
}

void ParticleTypeTable::setParticleType(int index, int type) {
    require(index >= 0, owner + ": particle index must be >= 0, got " + std::to_string(index));
    require(type >= 0, owner + ": particle type must be >= 0, got " + std::to_string(type));
    if (type == 0)
        particleType.erase(index);
    else
        particleType[index] = type;
}

void ParticleTypeTable::checkPairIndex(int pairIndex) const {
    require(pairIndex >= 0 && pairIndex < (int) typePairs.size(),
            owner + ": pairIndex must be in [0, " + std::to_string(typePairs.size()) + "), got " + std::to_string(pairIndex));
}

void ParticleTypeTable::checkTypePair(int type1, int type2, double value, double cutoff, int replacing) const {
    require(type1 >= 0, owner + ": type1 must be >= 0, got " + std::to_string(type1));
    require(type2 >= 0, owner + ": type2 must be >= 0, got " + std::to_string(type2));
    if (signedValues)
        require(std::isfinite(value), owner + ": " + valueName + " must be finite, got " + numberText(value));
    else
        require(std::isfinite(value) && value >= 0, owner + ": " + valueName + " must be >= 0 " + valueUnit + ", got " + numberText(value));
    require(std::isfinite(cutoff) && cutoff > 0, owner + ": cutoff must be > 0 nm, got " + numberText(cutoff));
    for (int i = 0; i < (int) typePairs.size(); i++) {
        const TypePair& p = typePairs[i];
        require(i == replacing || !((p.type1 == type1 && p.type2 == type2) || (p.type1 == type2 && p.type2 == type1)),
                owner + ": type pair (" + std::to_string(type1) + ", " + std::to_string(type2) +
                        ") must not be added twice; it is already entry " + std::to_string(i));
    }
}

int ParticleTypeTable::addTypePair(int type1, int type2, double value, double cutoff) {
    checkTypePair(type1, type2, value, cutoff, -1);
    typePairs.push_back({type1, type2, value, cutoff});
    return (int) typePairs.size() - 1;
}

const ParticleTypeTable::TypePair& ParticleTypeTable::getTypePair(int pairIndex) const {
    checkPairIndex(pairIndex);
    return typePairs[pairIndex];
}

void ParticleTypeTable::setTypePair(int pairIndex, int type1, int type2, double value, double cutoff) {
    checkPairIndex(pairIndex);
    checkTypePair(type1, type2, value, cutoff, pairIndex);
    typePairs[pairIndex] = {type1, type2, value, cutoff};
}

double ParticleTypeTable::getMaxCutoff(double defaultCutoff) const {
    double c = defaultCutoff;
    for (const TypePair& p : typePairs)
        c = std::max(c, p.cutoff);
    return c;
}

double ParticleTypeTable::getMaxValue(double defaultValue) const {
    double v = defaultValue;
    for (const TypePair& p : typePairs)
        v = std::max(v, p.value);
    return v;
}

void ParticleTypeTable::validate(const OpenMM::System& system) const {
    const int n = system.getNumParticles();
    std::set<int> usedTypes = {0};
    for (auto& entry : particleType) {
        require(entry.first < n, owner + ": setParticleType was given particle index " + std::to_string(entry.first) +
                ", but the System has only " + std::to_string(n) + " particles");
        usedTypes.insert(entry.second);
    }
    for (int i = 0; i < (int) typePairs.size(); i++)
        for (int t : {typePairs[i].type1, typePairs[i].type2})
            require(usedTypes.count(t) != 0, owner + ": type pair " + std::to_string(i) + " names particle type " +
                    std::to_string(t) + ", which no particle has (unknown particle type)");
}
