#ifndef OPENMMDPD_PRESSURETENSOR_H_
#define OPENMMDPD_PRESSURETENSOR_H_

#include "openmmdpd/CheckpointIO.h"
#include "openmmdpd/ConstrainedPairImpulse.h"
#include "openmmdpd/PairParameters.h"
#include "openmm/System.h"
#include "openmm/Vec3.h"
#include "openmm/internal/ContextImpl.h"
#include <array>
#include <string>
#include <type_traits>
#include <vector>

namespace DPDPlugin {

/** A symmetric 3x3 tensor as (xx, yy, zz, xy, xz, yz). */
using SymmetricTensor = std::array<double, 6>;

/** t += c e e^T for a unit vector e (the virial r F e e^T of a central pair force F e at distance r, c = r F). */
inline void addAlong(SymmetricTensor& t, const OpenMM::Vec3& e, double c) {
    t[0] += c * e[0] * e[0];
    t[1] += c * e[1] * e[1];
    t[2] += c * e[2] * e[2];
    t[3] += c * e[0] * e[1];
    t[4] += c * e[0] * e[2];
    t[5] += c * e[1] * e[2];
}

/**
 * t += the virial r F^T of a pair force F (on i) at separation r = r_i - r_j that need not be
 * along r (transverse friction), as the momentum flux the pressure tensor holds: the
 * diagonal r_a F_a, and for a < b the flux of a-momentum across planes of constant b,
 * r_b F_a (P_xy = sum y_ij F_x / V: the shear stress of flow along x with its gradient along
 * y).  For F along r it is addAlong's.
 */
inline void addOuter(SymmetricTensor& t, const OpenMM::Vec3& r, const OpenMM::Vec3& f) {
    t[0] += r[0] * f[0];
    t[1] += r[1] * f[1];
    t[2] += r[2] * f[2];
    t[3] += r[1] * f[0];
    t[4] += r[2] * f[0];
    t[5] += r[2] * f[1];
}

inline void addTensor(SymmetricTensor& t, const SymmetricTensor& u, double scale = 1) {
    for (int k = 0; k < 6; k++)
        t[k] += scale * u[k];
}

/** The distance of a thermostat pair, from its weight wR = 1 - r/rc. */
inline double pairDistance(const PairGeometry& p, const DPDPairParameters& parameters) {
    return parameters.pairCutoff(p.i, p.j) * (1 - p.wR);
}

/** virial += the virial of a pair force f on i at distance r: along e (addAlong) unless the pair has transverse friction (addOuter). */
inline void addPairForceVirial(SymmetricTensor& virial, const PairGeometry& p, double r, const OpenMM::Vec3& f) {
    if (p.hasTransverse())
        addOuter(virial, p.e * r, f);
    else
        addAlong(virial, p.e, r * f.dot(p.e));
}

/** virial += sum over the pairs of r_k c_k e_k e_k^T, for pair forces c_k e_k given per pair. */
inline void addPairVirial(const std::vector<PairGeometry>& pairs, const std::vector<double>& c, const DPDPairParameters& parameters,
                          SymmetricTensor& virial) {
    for (size_t k = 0; k < pairs.size(); k++)
        addAlong(virial, pairs[k].e, pairDistance(pairs[k], parameters) * c[k]);
}

/**
 * The impulses J (along e, on i; and across e, with transverse friction) that a
 * pairwise-sequential sweep gives each pair of its list, for the thermostat part of the
 * pressure tensor (docs/theory/pressure-tensor.md): the sweep's rules apply their impulses
 * through RecordedImpulse, which adds J to the pair's own entry, so a sweep split over
 * threads records without sharing an entry.
 */
class PairImpulseRecord {
public:
    /** Start recording a sweep over these pairs (the rules get references into the list). */
    void start(const std::vector<PairGeometry>& pairs, bool transverse) {
        first = pairs.data();
        impulse.assign(pairs.size(), 0.0);
        acrossImpulse.assign(transverse ? pairs.size() : 0, OpenMM::Vec3());
    }
    void add(const PairGeometry& p, double J) { impulse[&p - first] += J; }
    void addAcross(const PairGeometry& p, const OpenMM::Vec3& J) { acrossImpulse[&p - first] += J; }
    /** virial += scale * sum over the pairs of r J e e^T (and r J_perp^T, addOuter). */
    void addVirial(const std::vector<PairGeometry>& pairs, const DPDPairParameters& parameters, double scale,
                   SymmetricTensor& virial) const {
        for (size_t k = 0; k < pairs.size(); k++)
            if (impulse[k] != 0)
                addAlong(virial, pairs[k].e, scale * pairDistance(pairs[k], parameters) * impulse[k]);
        for (size_t k = 0; k < acrossImpulse.size(); k++)
            addOuter(virial, pairs[k].e * (scale * pairDistance(pairs[k], parameters)), acrossImpulse[k]);
    }

private:
    const PairGeometry* first = nullptr;
    std::vector<double> impulse;
    std::vector<OpenMM::Vec3> acrossImpulse;
};

/** A sweep's pair impulse that also records what it applies (Impulse: FreePairImpulse or ConstrainedPairImpulse). */
template <class Impulse>
struct RecordedImpulse {
    const Impulse& impulse;
    PairImpulseRecord& record;
    double inverseReducedMass(const PairGeometry& p) const { return impulse.inverseReducedMass(p); }
    double commonInverseReducedMass() const { return impulse.commonInverseReducedMass(); }
    void apply(const PairGeometry& p, double J, std::vector<OpenMM::Vec3>& v) const {
        impulse.apply(p, J, v);
        record.add(p, J);
    }
    void applyAcross(const PairGeometry& p, const OpenMM::Vec3& J, std::vector<OpenMM::Vec3>& v) const {
        impulse.applyAcross(p, J, v);
        record.addAcross(p, J);
    }
};

/**
 * withPairImpulse (ConstrainedPairImpulse.h) for a sweep over `pairs` of a step of length
 * dt.  Given a virial, body gets a RecordedImpulse, and the virial of the impulses,
 * sum r J e e^T / dt, is added to it afterwards.
 */
template <class Body>
void withRecordedPairImpulse(ConstrainedPairImpulse& constrained, const DPDPairParameters& parameters,
                             const std::vector<OpenMM::Vec3>& positions, const std::vector<PairGeometry>& pairs, double dt,
                             SymmetricTensor* virial, PairImpulseRecord& record, Body body) {
    if (virial == nullptr) {
        withPairImpulse(constrained, parameters.getInverseMasses(), positions, body);
        return;
    }
    record.start(pairs, parameters.hasTransverse());
    withPairImpulse(constrained, parameters.getInverseMasses(), positions, [&](const auto& impulse) {
        body(RecordedImpulse<std::decay_t<decltype(impulse)>>{impulse, record});
    });
    record.addVirial(pairs, parameters, 1 / dt, *virial);
}

/**
 * How the pressure tensor strains the Context's positions and box in place and puts them
 * back, on each platform in its own storage: not through ContextImpl::setPositions, which
 * would tell the integrator that the force it carries is stale, and on the GPU platforms not
 * through ContextImpl::setPeriodicBoxVectors, which refuses a triclinic box in a Context made
 * with a rectangular one and re-wraps the positions.
 */
class PositionStrain {
public:
    virtual ~PositionStrain() {}
    /**
     * Set every particle's position to x0 strained along a by b, x_a = x0_a + strain x0_b, x0
     * the positions of before the first strain since the last restore.
     */
    virtual void strain(OpenMM::ContextImpl& context, int a, int b, double strain) = 0;
    /** Put back the positions of before the first strain. */
    virtual void restore(OpenMM::ContextImpl& context) = 0;
    /** Set the periodic box vectors (a strained box, or the one to put back). */
    virtual void setBox(OpenMM::ContextImpl& context, const OpenMM::Vec3* box) = 0;
};

/** The running sums of the pressure tensor's samples. */
struct PressureSums {
    std::array<SymmetricTensor, 3> parts{};  // kinetic, conservative, thermostat: sum of P over samples
    long long count = 0;
};

/**
 * The pressure tensor of docs/theory/pressure-tensor.md, averaged over the steps since the last
 * reset: P = (1/V) [sum_i m_i u_i u_i + sum_{i<j} r_ij (FC + FD + FR)_ij], one sample at the
 * end of each step, kept as its three parts.
 *  - kinetic: the peculiar velocities u = v - rate (y - Ly/2) x (OpenMM's positions as stored)
 *    less their centre-of-mass velocity (the boundary jumps move the total momentum);
 *  - conservative: the integration force groups' virial.  A DPDSoftRepulsionForce gives its
 *    exact pair virial (the force's kernel); the other forces give -dU/d(epsilon) of their
 *    groups, the soft forces left out, by central differences over an affine strain of every
 *    particle and the box (atomic scaling: each particle's position is strained, molecules
 *    included, by the platform's PositionStrain);
 *  - thermostat: given by the step (the pair forces it applied, or the impulses of its
 *    sweeps over dt).
 * Constraint forces have no part in it, so Systems with constraints are refused.
 */
class PressureTensorSampler {
public:
    /** @param name  the integrator's class, for error messages */
    PressureTensorSampler(const OpenMM::System& system, const std::string& name);
    /** Add the sample of the step just taken (thermostatVirial: its sum of r_ij F_ij, kJ/mol). */
    void addSample(OpenMM::ContextImpl& context, double shearRate, int forceGroups, const SymmetricTensor& thermostatVirial,
                   PositionStrain& strain);
    /** The average of a part (DPDThermostatIntegrator::PressurePart), kJ/mol/nm^3. */
    std::vector<double> average(int part) const;
    long long getCount() const { return sums.count; }
    void reset();
    /** The sums over the samples so far (a checkpoint keeps them). */
    const PressureSums& getSums() const { return sums; }
    void setSums(const PressureSums& restored) { sums = restored; }

private:
    SymmetricTensor kineticTerm(OpenMM::ContextImpl& context, double shearRate) const;
    SymmetricTensor conservativeVirial(OpenMM::ContextImpl& context, int forceGroups, PositionStrain& strain) const;
    SymmetricTensor strainDerivative(OpenMM::ContextImpl& context, int groups, PositionStrain& strain) const;
    std::vector<double> mass;
    PressureSums sums;
};

/** The sums of a sampler (none: no samples) as a checkpoint holds them: the count, then each part's sum. */
void writePressureSums(std::ostream& stream, const PressureTensorSampler* sampler);
/** Read what writePressureSums() wrote; counts and sums that cannot be are refused. */
PressureSums readPressureSums(CheckpointReader& reader);

} // namespace DPDPlugin

#endif
