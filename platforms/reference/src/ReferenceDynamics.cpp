#include "openmmdpd/ReferenceDynamics.h"
#include "openmm/OpenMMException.h"
#include "openmmdpd/internal/ParameterChecks.h"
#include <algorithm>
#include <cmath>
#include <istream>

using namespace DPDPlugin;
using OpenMM::Vec3;

ReferenceDynamics::ReferenceDynamics(const OpenMM::System& system, const DPDThermostatIntegrator& integrator, int cellMultiple) :
        name(integrator.className()), parameters(system, integrator),
        random(PairRandom::seedFor(integrator.getRandomNumberSeed())),
        carried(system.getNumParticles()),
        pairList(parameters.getActive(), parameters.getMaxCutoff(), system.usesPeriodicBoundaryConditions(), cellMultiple),
        cellMultiple(cellMultiple), motion(system), shear(system) {
}

void ReferenceDynamics::updateParameters(const OpenMM::System& system, const DPDThermostatIntegrator& integrator) {
    parameters = DPDPairParameters(system, integrator);
    pairList = ReferencePairList(parameters.getActive(), parameters.getMaxCutoff(), system.usesPeriodicBoundaryConditions(),
                                 cellMultiple);
}

std::vector<PairGeometry> ReferenceDynamics::findPairs(OpenMM::ContextImpl& context) const {
    Vec3 box[3];
    context.getPeriodicBoxVectors(box[0], box[1], box[2]);
    if (context.getSystem().usesPeriodicBoundaryConditions())
        requireCutoffFitsBox(name, "the thermostat cutoff", parameters.getMaxCutoff(), box);
    const std::vector<Vec3>& r = *data(context).positions;
    std::vector<PairGeometry> pairs;
    PairGeometry g;
    for (const ReferencePair& p : pairList.find(r, box))
        if (parameters.pairGeometry(p.i, p.j, p.d, g, parameters.imageVelocityX(r[p.i][1] - r[p.j][1], p.d[1], box[1][1])))
            pairs.push_back(g);
    return pairs;
}

std::vector<Vec3> ReferenceDynamics::conservativeForce(OpenMM::ContextImpl& context, int forceGroups, long long step) const {
    context.calcForcesAndEnergy(true, false, forceGroups);
    const std::vector<Vec3> force = *data(context).forces;
    checkFinite(force, "conservative force", step, name);
    return force;
}

void ReferenceDynamics::addDissipative(const std::vector<PairGeometry>& pairs, const std::vector<Vec3>& v, std::vector<Vec3>& out,
                                       SymmetricTensor* virial) const {
    for (const PairGeometry& p : pairs)
        addPairForce(p, DPDPairForce::dissipative(p, p.relativeVelocity(v[p.i], v[p.j])), out, virial);
}

void ReferenceDynamics::addRandom(const std::vector<PairGeometry>& pairs, long long step, double dt, std::vector<Vec3>& out,
                                  SymmetricTensor* virial) const {
    for (const PairGeometry& p : pairs) {
        const double xi = random.gaussian(PairRandom::RandomForce, step, p.i, p.j);
        Vec3 f = DPDPairForce::random(p, xi, 1 / std::sqrt(dt));
        if (p.hasTransverse()) {
            double zeta[3];
            random.normalVector(PairRandom::TransverseNoise, step, p.i, p.j, zeta);
            f += DPDPairForce::transverseRandom(p, zeta, 1 / std::sqrt(dt));
        }
        addPairForce(p, f, out, virial);
    }
}

void ReferenceDynamics::addPairForce(const PairGeometry& p, const Vec3& f, std::vector<Vec3>& out, SymmetricTensor* virial) const {
    out[p.i] += f;
    out[p.j] -= f;
    if (virial != nullptr)
        addPairForceVirial(*virial, p, pairDistance(p, parameters), f);
}

void ReferenceDynamics::movePositions(OpenMM::ContextImpl& context, const std::vector<Vec3>& move, long long step, double dt,
                                      std::vector<Vec3>* alsoCorrect) {
    std::vector<Vec3>& r = *data(context).positions;
    motion.startDrift(r);
    double maxMove2 = 0;
    for (size_t i = 0; i < r.size(); i++) {
        r[i] += move[i];
        maxMove2 = std::max(maxMove2, move[i].dot(move[i]));
    }
    checkFinite(r, "position", step, name);
    checkMove(maxMove2, parameters.getMaxCutoff(), step, name);
    motion.finishDrift(context, dt, alsoCorrect);
    shear.slide(context, parameters.getShearRate(), dt, r, *data(context).velocities, alsoCorrect);
}

double ReferenceDynamics::sumMV2(const std::vector<Vec3>& v) const {
    double sum = 0;
    for (size_t i = 0; i < v.size(); i++)
        sum += parameters.getMasses()[i] * v[i].dot(v[i]);
    return sum;
}

double ReferenceDynamics::computeKineticEnergy(OpenMM::ContextImpl& context) const {
    return 0.5 * sumMV2(*data(context).velocities);
}

void ReferenceDynamics::finishStep(OpenMM::ContextImpl& context, double dt) const {
    OpenMM::ReferencePlatform::PlatformData& state = data(context);
    checkVelocities(*state.velocities, parameters, state.stepCount + 1, name);
    state.stepCount++;
    state.time += dt;
}

void ReferenceDynamics::createCheckpoint(std::ostream& stream) const {
    carried.write(stream, random.getSeed());
    saveExtraState(stream);
}

void ReferenceDynamics::loadCheckpoint(OpenMM::ContextImpl& context, CheckpointReader& reader) {
    CarriedForce loaded(parameters.getNumParticles());
    const uint32_t seed = loaded.read(reader, *data(context).positions, *data(context).velocities);
    loadExtraState(reader);
    reader.expectEnd();
    commitExtraState();
    carried = std::move(loaded);
    random = PairRandom(seed);
}

void ReferenceDynamics::resetState() {
    carried = CarriedForce(parameters.getNumParticles());
    resetExtraState();
}
