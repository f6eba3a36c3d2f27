#include "openmmdpd/PairParameters.h"
#include "openmm/OpenMMException.h"
#include <algorithm>
#include <map>

using namespace DPDPlugin;
using OpenMM::Vec3;

TypePairTable::TypePairTable(int numParticles, const std::map<int, int>& particleTypes, double defaultValue, double defaultCutoff,
                             const std::vector<Entry>& entries, double defaultExponent, Transverse defaultTransverse) {
    // Dense indices for the types in use (type 0 always exists: it is everyone's default).
    std::map<int, int> dense = {{0, 0}};
    for (auto& entry : particleTypes)
        dense.emplace(entry.second, 0);
    int next = 0;
    for (auto& entry : dense)
        entry.second = next++;
    numTypes = next;
    typeIndex.assign(numParticles, 0);
    for (auto& entry : particleTypes)
        typeIndex[entry.first] = dense[entry.second];
    values.assign(numTypes * numTypes, defaultValue);
    cutoffs.assign(numTypes * numTypes, defaultCutoff);
    exponents.assign(numTypes * numTypes, defaultExponent);
    transverse.assign(numTypes * numTypes, defaultTransverse);
    for (const Entry& e : entries) {
        const int a = dense.at(e.type1), b = dense.at(e.type2);
        values[a * numTypes + b] = values[b * numTypes + a] = e.value;
        cutoffs[a * numTypes + b] = cutoffs[b * numTypes + a] = e.cutoff;
        exponents[a * numTypes + b] = exponents[b * numTypes + a] = e.exponent;
        transverse[a * numTypes + b] = transverse[b * numTypes + a] = e.transverse;
    }
    standardWeights = std::all_of(exponents.begin(), exponents.end(), [](double s) { return s == 2; });
    anyTransverse = std::any_of(transverse.begin(), transverse.end(), [](const Transverse& t) { return t.value != 0; });
    maxCutoff = *std::max_element(cutoffs.begin(), cutoffs.end());
    cutoffs2.resize(cutoffs.size());
    inverseCutoffs.resize(cutoffs.size());
    for (size_t k = 0; k < cutoffs.size(); k++) {
        cutoffs2[k] = cutoffs[k] * cutoffs[k];
        inverseCutoffs[k] = 1 / cutoffs[k];
    }
}

namespace {

TypePairTable thermostatTable(const OpenMM::System& system, const DPDThermostatIntegrator& integrator) {
    std::vector<TypePairTable::Entry> entries(integrator.getNumTypePairs());
    for (int k = 0; k < integrator.getNumTypePairs(); k++) {
        TypePairTable::Entry& e = entries[k];
        integrator.getTypePairParameters(k, e.type1, e.type2, e.value, e.cutoff);
        e.exponent = integrator.getTypePairWeightExponent(k);
        integrator.getTypePairTransverseFriction(k, e.transverse.value, e.transverse.exponent);
    }
    TypePairTable::Transverse transverse;
    transverse.value = integrator.getDefaultTransverseFriction();
    transverse.exponent = integrator.getDefaultTransverseWeightExponent();
    return TypePairTable(system.getNumParticles(), integrator.getParticleTypes(), integrator.getDefaultFriction(),
                         integrator.getDefaultCutoff(), entries, integrator.getDefaultWeightExponent(), transverse);
}

} // namespace

DPDPairParameters::DPDPairParameters(const OpenMM::System& system, const DPDThermostatIntegrator& integrator) :
        table(thermostatTable(system, integrator)), kT(BOLTZMANN_KJ_PER_MOL_K * integrator.getTemperature()),
        instabilityThreshold(integrator.getInstabilityThreshold()),
        shearRate(integrator.getShearRate()) {
    const int n = system.getNumParticles();
    mass.resize(n);
    invMass.resize(n);
    active.resize(n);
    for (int i = 0; i < n; i++) {
        mass[i] = system.getParticleMass(i);
        active[i] = (mass[i] > 0);
        invMass[i] = active[i] ? 1 / mass[i] : 0;
    }
    uniformMass = true;
    int first = -1;
    for (int i = 0; i < n; i++)
        if (active[i]) {
            if (first < 0)
                first = i;
            uniformMass = uniformMass && mass[i] == mass[first];
        }
    if (uniformMass && first >= 0) {
        // The same arithmetic as pairGamma() and noiseAmplitude(), so either path gives the same bits.
        for (int t = 0; t < table.getNumTypes() * table.getNumTypes(); t++) {
            const double gamma = reducedMassTwice(first, first) * table.value(t);
            typeGamma.push_back(gamma);
            typeSigma.push_back(noiseAmplitude(gamma));
            typeTransverseGamma.push_back(reducedMassTwice(first, first) * table.transverseValue(t));
        }
    }
    else
        uniformMass = false;
    listExceptions(integrator);
}

void DPDPairParameters::listExceptions(const DPDThermostatIntegrator& integrator) {
    const int numExceptions = integrator.getNumThermostatExceptions();
    if (numExceptions == 0)
        return;
    std::vector<std::vector<std::pair<int, double>>> byLower(mass.size());
    for (int k = 0; k < numExceptions; k++) {
        int p1, p2;
        double f;
        integrator.getThermostatExceptionParameters(k, p1, p2, f);
        byLower[std::min(p1, p2)].push_back({std::max(p1, p2), f});
    }
    exceptionStart.assign(1, 0);
    for (const auto& partners : byLower) {
        for (const auto& partner : partners) {
            exceptionPartner.push_back(partner.first);
            exceptionFactor.push_back(partner.second);
        }
        exceptionStart.push_back((int) exceptionPartner.size());
    }
}

