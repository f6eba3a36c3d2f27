#ifndef OPENMMDPD_PAIRPARAMETERS_H_
#define OPENMMDPD_PAIRPARAMETERS_H_

#include "openmmdpd/BoxGeometry.h"
#include "openmmdpd/DPDThermostatIntegrator.h"
#include "openmmdpd/PairFormulas.h"
#include "openmm/System.h"
#include "openmm/Vec3.h"
#include <algorithm>
#include <cmath>
#include <map>
#include <vector>

namespace DPDPlugin {

/**
 * One pair within its thermostat cutoff, with everything the pair rules need at the
 * current positions: the unit vector e = r_ij / r (minimum image), the linear weight
 * wR = 1 - r/rc (the random weight of the standard exponent s = 2), and the pair's weighted
 * friction gamma_ij wD = gamma_ij (1 - r/rc)^s, weighted noise amplitude
 * sigma_ij (1 - r/rc)^(s/2), and its type pair's friction rate (1/ps; Lowe-Andersen's
 * collision rate Gamma).  Under shear, imageVx is the x velocity of the image of j that
 * r_ij points to, relative to j itself (0 within the box).  With transverse friction, the
 * friction and noise across e, weighted with their own exponent: gamma_perp wD_perp and
 * sigma_perp wR_perp (both 0 without).
 */
struct PairGeometry {
    int i, j;
    OpenMM::Vec3 e;
    double wR, gammaWD, sigmaWR, rate, imageVx;
    double transverseGammaWD = 0, transverseSigmaWR = 0;  // (0 unless set: most code makes pairs without it)

    /** v_ij = v_i - v_j, with j moving as its image does. */
    OpenMM::Vec3 relativeVelocity(const OpenMM::Vec3& vi, const OpenMM::Vec3& vj) const {
        OpenMM::Vec3 v = vi - vj;
        v[0] -= imageVx;
        return v;
    }
    /** Whether the pair has friction across e (its pair forces and impulses are then not along e). */
    bool hasTransverse() const { return transverseGammaWD != 0; }
    /** The part of x perpendicular to e, (I - e e^T) x. */
    OpenMM::Vec3 perpendicular(const OpenMM::Vec3& x) const {
        const double eDotX = e.dot(x);
        return OpenMM::Vec3(perpendicularPart(x[0], eDotX, e[0]), perpendicularPart(x[1], eDotX, e[1]),
                            perpendicularPart(x[2], eDotX, e[2]));
    }
};

/**
 * A per-type-pair table of one parameter, a cutoff and a weight exponent, resolved for
 * lookup by particle: the particle types in use get dense indices, and pairs of types
 * without an entry get the defaults.  The thermostats (friction, and the exponent s of their
 * weights; a transverse friction and its exponent) and the soft repulsion force (a; the
 * rest unused) both use it.
 */
/** A type pair's transverse friction and its weight exponent (or the defaults'). */
struct TypePairTransverse {
    double value = 0, exponent = 2;
};

class TypePairTable {
public:
    typedef TypePairTransverse Transverse;
    struct Entry {
        int type1, type2;
        double value, cutoff, exponent = 2;
        Transverse transverse;
    };
    TypePairTable(int numParticles, const std::map<int, int>& particleTypes, double defaultValue, double defaultCutoff,
                  const std::vector<Entry>& entries, double defaultExponent = 2, Transverse defaultTransverse = Transverse());
    /** The table index of the pair (i, j). */
    int index(int i, int j) const { return typeIndex[i] * numTypes + typeIndex[j]; }
    /** The dense type of a particle, and the table index of a pair of dense types. */
    int typeOf(int particle) const { return typeIndex[particle]; }
    int indexOfTypes(int a, int b) const { return a * numTypes + b; }
    double value(int t) const { return values[t]; }
    double cutoff(int t) const { return cutoffs[t]; }
    double cutoff2(int t) const { return cutoffs2[t]; }
    double inverseCutoff(int t) const { return inverseCutoffs[t]; }
    double exponent(int t) const { return exponents[t]; }
    double transverseValue(int t) const { return transverse[t].value; }
    double transverseExponent(int t) const { return transverse[t].exponent; }
    /** Whether every type pair has the standard weight exponent 2. */
    bool hasStandardWeights() const { return standardWeights; }
    /** Whether any type pair has a transverse friction. */
    bool hasTransverse() const { return anyTransverse; }
    double getMaxCutoff() const { return maxCutoff; }
    int getNumTypes() const { return numTypes; }

private:
    int numTypes;
    double maxCutoff;
    bool standardWeights, anyTransverse;
    std::vector<int> typeIndex;
    std::vector<double> values, cutoffs, cutoffs2, inverseCutoffs, exponents;
    std::vector<Transverse> transverse;
};

/**
 * The thermostat parameters of a System resolved per particle and per pair: the type-pair
 * friction/cutoff table, masses, kT and the instability threshold.  Built once per Context from any
 * DPDThermostatIntegrator.
 */
class DPDPairParameters {
public:
    DPDPairParameters(const OpenMM::System& system, const DPDThermostatIntegrator& integrator);
    int getNumParticles() const { return (int) mass.size(); }
    double getMaxCutoff() const { return table.getMaxCutoff(); }
    const TypePairTable& getTable() const { return table; }
    /** Particles that move and take part in the thermostat (mass > 0). */
    const std::vector<bool>& getActive() const { return active; }
    const std::vector<double>& getMasses() const { return mass; }
    /** Whether every particle that takes part has the same mass. */
    bool hasUniformMass() const { return uniformMass; }
    const std::vector<double>& getInverseMasses() const { return invMass; }
    double getKT() const { return kT; }
    /** The integrator's instability threshold (a multiple of kT; 0 = off). */
    double getInstabilityThreshold() const { return instabilityThreshold; }
    /** The integrator's shear rate (1/ps; 0 = no shear). */
    double getShearRate() const { return shearRate; }
    /**
     * Under shear, the x velocity of the image of j at r_i - d relative to j: n U, with n =
     * (y_ij - d_y) / Ly the boundary crossings between the two (docs/theory/lees-edwards.md: from
     * the same image the distance came from) and U = rate Ly.
     *
     * @param yij  y_i - y_j of the positions as stored
     * @param dy   the y component of the displacement d the pair search found
     * @param Ly   the box height
     */
    double imageVelocityX(double yij, double dy, double Ly) const {
        return shearRate == 0 ? 0.0 : roundToInteger((yij - dy) / Ly) * shearRate * Ly;
    }
    /**
     * The geometry of a pair at displacement d = r_i - r_j (nearest image) whose partner's
     * image moves at imageVx (see imageVelocityX); returns false if the pair is beyond its
     * own type-pair cutoff.
     */
    bool pairGeometry(int i, int j, const OpenMM::Vec3& d, PairGeometry& out, double imageVx = 0) const {
        return pairGeometry(i, j, table.index(i, j), d, out, imageVx);
    }
    /**
     * The same, given the pair's table index t = getTable().index(i, j): for a caller that
     * keeps the particles' types in its own order (looking them up by particle index hits
     * memory at random in a large system).
     */
    bool pairGeometry(int i, int j, int t, const OpenMM::Vec3& d, PairGeometry& out, double imageVx = 0) const {
        const double r2 = d.dot(d);
        if (r2 >= table.cutoff2(t) || r2 == 0)
            return false;
        const double r = std::sqrt(r2);
        const double w = pairLinearWeight(r, table.cutoff(t));
        double gamma, sigma;
        if (uniformMass) {
            gamma = typeGamma[t];
            sigma = typeSigma[t];
        }
        else {
            gamma = pairGamma(i, j);
            sigma = noiseAmplitude(gamma);
        }
        out.i = i;
        out.j = j;
        out.e = d / r;
        const double wR = pairRandomWeight(w, table.exponent(t));
        out.wR = w;
        out.gammaWD = gamma * pairDissipativeWeight(wR);
        out.sigmaWR = sigma * wR;
        out.rate = table.value(t);
        out.imageVx = imageVx;
        out.transverseGammaWD = out.transverseSigmaWR = 0;
        if (table.hasTransverse())
            setTransverse(out, t, w);
        if (!exceptionStart.empty())
            scaleByException(out);
        return true;
    }
    /** Whether any pair has a thermostat exception (DPDThermostatIntegrator::addThermostatException). */
    bool hasExceptions() const { return !exceptionStart.empty(); }
    /**
     * The exceptions listed by the lower particle index: the partners and factors of particle
     * i are at [start[i], start[i+1]) (start is empty without exceptions).
     */
    const std::vector<int>& getExceptionStart() const { return exceptionStart; }
    const std::vector<int>& getExceptionPartner() const { return exceptionPartner; }
    const std::vector<double>& getExceptionFactor() const { return exceptionFactor; }
    /** The thermostat factor f of the pair (i, j): its exception's, else 1. */
    double pairFactor(int i, int j) const {
        if (exceptionStart.empty())
            return 1;
        const int lo = std::min(i, j), hi = std::max(i, j);
        for (int k = exceptionStart[lo]; k < exceptionStart[lo + 1]; k++)
            if (exceptionPartner[k] == hi)
                return exceptionFactor[k];
        return 1;
    }
    /** Whether any pair has transverse friction. */
    bool hasTransverse() const { return table.hasTransverse(); }
    /** gamma and sigma of every pair of table index t where masses are uniform (hasUniformMass), as pairGeometry takes them. */
    double uniformGamma(int t) const { return typeGamma[t]; }
    double uniformSigma(int t) const { return typeSigma[t]; }
    /** sigma = sqrt(2 gamma kT), the fluctuation-dissipation partner of a friction gamma. */
    double noiseAmplitude(double gamma) const { return pairNoiseAmplitude(gamma, kT); }

    /** The friction coefficient gamma_ij = 2 mu_ij friction_ij of any pair (amu/ps). */
    double pairGamma(int i, int j) const { return reducedMassTwice(i, j) * table.value(table.index(i, j)); }
    /** gamma_ij f_ij: the friction coefficient of any pair scaled by its thermostat exception (amu/ps). */
    double pairThermostatGamma(int i, int j) const { return pairGamma(i, j) * pairFactor(i, j); }
    /** The cutoff of any pair (nm). */
    double pairCutoff(int i, int j) const { return table.cutoff(table.index(i, j)); }

private:
    void listExceptions(const DPDThermostatIntegrator& integrator);
    double reducedMassTwice(int i, int j) const { return 2 * mass[i] * mass[j] / (mass[i] + mass[j]); }
    /** The transverse friction and noise of a pair of table index t and linear weight w. */
    void setTransverse(PairGeometry& p, int t, double w) const {
        const double gamma = uniformMass ? typeTransverseGamma[t] : reducedMassTwice(p.i, p.j) * table.transverseValue(t);
        const double wR = pairRandomWeight(w, table.transverseExponent(t));
        p.transverseGammaWD = gamma * pairDissipativeWeight(wR);
        p.transverseSigmaWR = noiseAmplitude(gamma) * wR;
    }
    /** gamma by f, sigma by sqrt(f) (along e and across) and Lowe's collision rate by f, for a pair with an exception. */
    void scaleByException(PairGeometry& p) const {
        const double f = pairFactor(p.i, p.j);
        if (f != 1) {
            p.gammaWD *= f;
            p.sigmaWR *= std::sqrt(f);
            p.rate *= f;
            p.transverseGammaWD *= f;
            p.transverseSigmaWR *= std::sqrt(f);
        }
    }
    TypePairTable table;
    double kT, instabilityThreshold, shearRate;
    // The exceptions by the lower particle index: partners and factors of particle i at [exceptionStart[i], exceptionStart[i+1]).
    std::vector<int> exceptionStart, exceptionPartner;
    std::vector<double> exceptionFactor;
    std::vector<double> mass, invMass;
    std::vector<bool> active;
    // When every particle has one mass (the usual DPD fluid), gamma and sigma depend on the
    // type pair alone and are looked up instead of computed per pair.
    bool uniformMass;
    std::vector<double> typeGamma, typeSigma, typeTransverseGamma;
};

} // namespace DPDPlugin

#endif
