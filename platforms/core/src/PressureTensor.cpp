#include "openmmdpd/PressureTensor.h"
#include "openmmdpd/DPDKernels.h"
#include "openmmdpd/internal/PairVirialForceImpl.h"
#include "openmm/OpenMMException.h"

using namespace DPDPlugin;
using OpenMM::Vec3;

namespace {

/** The relative strain of the central differences (small against 1, large against float rounding of the energy). */
constexpr double STRAIN_STEP = 1e-3;
/** The strains x += e y etc. that keep OpenMM's box in its reduced (lower-triangular) form, in tensor order. */
constexpr int STRAIN_AXES[6][2] = {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {0, 2}, {1, 2}};

/** Bring box vectors b and c back into OpenMM's reduced form after a strain (the same lattice). */
void reduceBox(Vec3* box) {
    for (int k = 2; k >= 1; k--)
        for (int m = k - 1; m >= 0; m--) {
            while (box[k][m] > 0.5 * box[m][m])
                box[k] -= box[m];
            while (box[k][m] < -0.5 * box[m][m])
                box[k] += box[m];
        }
}

} // namespace

PressureTensorSampler::PressureTensorSampler(const OpenMM::System& system, const std::string& name) {
    if (system.getNumConstraints() > 0)
        throw OpenMM::OpenMMException(name + ": the pressure tensor (setPressureTensorEnabled) leaves out constraint forces, "
                                      "so it is not available for a System with constraints");
    for (int i = 0; i < system.getNumParticles(); i++)
        mass.push_back(system.getParticleMass(i));
}

void PressureTensorSampler::addSample(OpenMM::ContextImpl& context, double shearRate, int forceGroups,
                                      const SymmetricTensor& thermostatVirial, PositionStrain& strain) {
    Vec3 box[3];
    context.getPeriodicBoxVectors(box[0], box[1], box[2]);
    const double inverseVolume = 1 / (box[0][0] * box[1][1] * box[2][2]);
    addTensor(sums.parts[0], kineticTerm(context, shearRate), inverseVolume);
    addTensor(sums.parts[1], conservativeVirial(context, forceGroups, strain), inverseVolume);
    addTensor(sums.parts[2], thermostatVirial, inverseVolume);
    sums.count++;
}

std::vector<double> PressureTensorSampler::average(int part) const {
    SymmetricTensor total{};
    if (part == DPDThermostatIntegrator::PressureTotal)
        for (const SymmetricTensor& s : sums.parts)
            addTensor(total, s);
    else
        total = sums.parts[part - 1];
    std::vector<double> result(6);
    for (int k = 0; k < 6; k++)
        result[k] = total[k] / sums.count;
    return result;
}

void PressureTensorSampler::reset() {
    sums = PressureSums();
}

void DPDPlugin::writePressureSums(std::ostream& stream, const PressureTensorSampler* sampler) {
    const PressureSums sums = sampler ? sampler->getSums() : PressureSums();
    putField<int64_t>(stream, sums.count);
    for (const SymmetricTensor& part : sums.parts)
        for (double x : part)
            putField<double>(stream, x);
}

PressureSums DPDPlugin::readPressureSums(CheckpointReader& reader) {
    PressureSums sums;
    sums.count = reader.take<int64_t>("the pressure tensor's sample count");
    if (sums.count < 0 || sums.count > MAX_STEP_NUMBER)
        reader.damaged("the pressure tensor's sample count is " + std::to_string(sums.count));
    for (SymmetricTensor& part : sums.parts)
        for (double& x : part)
            x = reader.takeFinite("a pressure tensor sum");
    return sums;
}

SymmetricTensor PressureTensorSampler::kineticTerm(OpenMM::ContextImpl& context, double shearRate) const {
    std::vector<Vec3> r, v;
    context.getPositions(r);
    context.getVelocities(v);
    Vec3 box[3];
    context.getPeriodicBoxVectors(box[0], box[1], box[2]);
    std::vector<Vec3> u(v.size());
    Vec3 momentum;
    double totalMass = 0;
    for (size_t i = 0; i < v.size(); i++) {
        u[i] = v[i];
        u[i][0] -= shearRate * (r[i][1] - 0.5 * box[1][1]);
        momentum += u[i] * mass[i];
        totalMass += mass[i];
    }
    const Vec3 mean = (totalMass > 0 ? momentum / totalMass : Vec3());
    SymmetricTensor t{};
    for (size_t i = 0; i < v.size(); i++) {
        const Vec3 w = u[i] - mean;
        t[0] += mass[i] * w[0] * w[0];
        t[1] += mass[i] * w[1] * w[1];
        t[2] += mass[i] * w[2] * w[2];
        t[3] += mass[i] * w[0] * w[1];
        t[4] += mass[i] * w[0] * w[2];
        t[5] += mass[i] * w[1] * w[2];
    }
    return t;
}

namespace {

/** Leaves the pair-virial forces out of the Context's force evaluations while it lives (PairVirialForceImpl::setLeftOut). */
class PairVirialForcesLeftOut {
public:
    explicit PairVirialForcesLeftOut(const std::vector<PairVirialForceImpl*>& forces) : forces(forces) {
        for (PairVirialForceImpl* force : forces)
            force->setLeftOut(true);
    }
    ~PairVirialForcesLeftOut() {
        for (PairVirialForceImpl* force : forces)
            force->setLeftOut(false);
    }

private:
    const std::vector<PairVirialForceImpl*>& forces;
};

} // namespace

SymmetricTensor PressureTensorSampler::conservativeVirial(OpenMM::ContextImpl& context, int forceGroups,
                                                         PositionStrain& strain) const {
    // Every force with an exact pair virial (the soft repulsion, MDPD) gives it, and is left
    // out of the strain of the other forces of its group.
    SymmetricTensor virial{};
    std::vector<PairVirialForceImpl*> pairForces;
    int otherGroups = 0;
    for (OpenMM::ForceImpl* impl : context.getForceImpls()) {
        const int group = 1 << impl->getOwner().getForceGroup();
        if ((forceGroups & group) == 0)
            continue;
        PairVirialForceImpl* pairForce = dynamic_cast<PairVirialForceImpl*>(impl);
        if (pairForce == nullptr) {
            otherGroups |= group;
            continue;
        }
        addTensor(virial, pairForce->computeVirial(context));
        pairForces.push_back(pairForce);
    }
    if (otherGroups != 0) {
        PairVirialForcesLeftOut leftOut(pairForces);
        addTensor(virial, strainDerivative(context, otherGroups, strain));
    }
    return virial;
}

namespace {

/** Puts back the positions, the box and the last force groups when it goes, also when an evaluation under the strain throws. */
class StrainedState {
public:
    StrainedState(OpenMM::ContextImpl& context, PositionStrain& strain) :
            context(context), strain(strain), lastGroups(context.getLastForceGroups()) {
        context.getPeriodicBoxVectors(box[0], box[1], box[2]);
    }
    ~StrainedState() {
        try {
            strain.restore(context);
            strain.setBox(context, box);
            context.getLastForceGroups() = lastGroups;
        }
        catch (...) {
            // A destructor must not throw; the error that ended the strain is the one to report.
        }
    }
    Vec3 box[3];

private:
    OpenMM::ContextImpl& context;
    PositionStrain& strain;
    int lastGroups;
};

} // namespace

SymmetricTensor PressureTensorSampler::strainDerivative(OpenMM::ContextImpl& context, int groups, PositionStrain& strain) const {
    StrainedState strained(context, strain);
    SymmetricTensor virial{};
    for (int k = 0; k < 6; k++) {
        const int a = STRAIN_AXES[k][0], b = STRAIN_AXES[k][1];
        double energy[2];
        for (int side = 0; side < 2; side++) {
            const double epsilon = (side == 0 ? STRAIN_STEP : -STRAIN_STEP);
            strain.strain(context, a, b, epsilon);
            Vec3 box[3] = {strained.box[0], strained.box[1], strained.box[2]};
            for (Vec3& edge : box)
                edge[a] += epsilon * edge[b];
            reduceBox(box);
            strain.setBox(context, box);
            energy[side] = context.calcForcesAndEnergy(false, true, groups);
        }
        // W_ab = sum r_b F_a = -dU/d(strain)
        virial[k] = -(energy[0] - energy[1]) / (2 * STRAIN_STEP);
    }
    return virial;
}
