#include "openmmdpd/CheckpointIO.h"
#include "openmmdpd/ReferenceStaggeredDynamics.h"
#include "openmmdpd/StaggeredSteps.h"
#include "openmm/OpenMMException.h"
#include <istream>
#include <ostream>

using namespace DPDPlugin;
using OpenMM::Vec3;

// Notation of docs/theory/staggered.md: s solvent, p polymer (the particles the fast forces
// act on), Dt the outer step, dt = Dt/K the sub-step, F the slow force carried from the last
// outer step, F^ the one evaluated in this one, Fp the fast force.

ReferenceStaggeredDynamics::ReferenceStaggeredDynamics(const OpenMM::System& system, const StaggeredDPDIntegrator& integrator) :
        // The Lowe base sweeps the pairs in the coloured order of LoweAndersenIntegrator.
        ReferenceDynamics(system, integrator, integrator.getBaseScheme() == StaggeredDPDIntegrator::LoweAndersen ? 3 : 1),
        baseScheme(integrator.getBaseScheme()) {
    updatePolymer(system, integrator);
}

void ReferenceStaggeredDynamics::updatePolymer(const OpenMM::System& system, const StaggeredDPDIntegrator& integrator) {
    polymer.select(system, integrator);
    Fp.assign(polymer.particles.size(), Vec3());
}

std::vector<Vec3> ReferenceStaggeredDynamics::slowForce(OpenMM::ContextImpl& context, const StaggeredDPDIntegrator& integrator,
                                                        const std::vector<Vec3>& u, long long step) {
    const int slowGroups = integrator.getIntegrationForceGroups() & ~integrator.getFastForceGroups();
    std::vector<Vec3> F = conservativeForce(context, slowGroups, step);
    if (baseScheme == StaggeredDPDIntegrator::VelocityVerlet) {
        const std::vector<PairGeometry> pairs = findPairs(context);
        addDissipative(pairs, u, F);
        addRandom(pairs, step, integrator.getStepSize(), F);
    }
    return F;
}

std::vector<Vec3> ReferenceStaggeredDynamics::fastForce(OpenMM::ContextImpl& context, const StaggeredDPDIntegrator& integrator,
                                                        long long step) {
    context.calcForcesAndEnergy(true, false, integrator.getFastForceGroups());
    const std::vector<Vec3>& f = *data(context).forces;
    std::vector<Vec3> fast(polymer.particles.size());
    for (size_t k = 0; k < polymer.particles.size(); k++)
        fast[k] = f[polymer.particles[k]];
    checkFinite(fast, polymer.particles, "fast force", step, name);
    if (polymer.checkFastForceOutside)
        checkOutsidePolymer(f, polymer.index, step, name);
    return fast;
}

void ReferenceStaggeredDynamics::step(OpenMM::ContextImpl& context, const StaggeredDPDIntegrator& integrator) {
    requireBaseScheme(integrator, baseScheme);
    std::vector<Vec3>& r = *data(context).positions;
    std::vector<Vec3>& v = *data(context).velocities;
    const long long current = data(context).stepCount;
    bool valid = carried.isValid(r, v);
    if (polymer.changed(integrator)) {
        updatePolymer(context.getSystem(), integrator);
        valid = false;
    }
    if (!valid) {
        carried.force = slowForce(context, integrator, v, current);
        Fp = fastForce(context, integrator, current);
        carried.setValid();
    }
    const StepStart start(context, r, v);
    const std::vector<Vec3> predicted = predict(context, integrator);
    // F^ = F(r_s, r^^_p ; u^_s, u^^_p): the one slow evaluation of the outer step.
    const std::vector<Vec3> newF = slowForce(context, integrator, predicted, current + 1);
    kickSolvent(context, integrator, newF);
    subCycle(context, integrator, start, newF);
    carried.force = newF;
    if (baseScheme == StaggeredDPDIntegrator::LoweAndersen)
        thermalise(context, integrator, current);
    finishStep(context, integrator.getStepSize());
}

std::vector<Vec3> ReferenceStaggeredDynamics::predict(OpenMM::ContextImpl& context, const StaggeredDPDIntegrator& integrator) {
    std::vector<Vec3>& r = *data(context).positions;
    const std::vector<Vec3>& u = *data(context).velocities;
    const std::vector<Vec3>& F = carried.force;
    const std::vector<double>& invMass = parameters.getInverseMasses();
    const double Dt = integrator.getStepSize(), lambda = integrator.getLambda(), mu = integrator.getMu(), a = integrator.getA();
    const size_t n = r.size();
    std::vector<Vec3> move(n), predicted(n);
    for (size_t i = 0; i < n; i++) {
        const int k = polymer.index[i];
        // The force the particle feels: F_s, or F_p + Fp_p.
        const Vec3 f = (k >= 0 ? F[i] + Fp[k] : F[i]);
        // r_s <- r_s + Dt u_s + Dt^2/(2m) F_s
        // r^_p = r_p + Dt u_p + Dt^2/(2m) (F_p + Fp_p) ;  r^^_p = mu r_p + (1 - mu) r^_p
        move[i] = u[i] * Dt + f * (0.5 * Dt * Dt * invMass[i]);
        if (k >= 0)
            move[i] = move[i] * (1 - mu);
        // u^_s = u_s + lambda Dt F_s/m
        // u^_p = u_p + lambda Dt (F_p + Fp_p)/m ;  u^^_p = a u_p + (1 - a) u^_p
        predicted[i] = u[i] + f * (lambda * Dt * invMass[i]);
        if (k >= 0)
            predicted[i] = u[i] * a + predicted[i] * (1 - a);
    }
    // Under shear the predicted velocities take the jumps of the molecules that cross, as
    // their positions do: F^'s dissipative force pairs them with the wrapped positions.
    movePositions(context, move, data(context).stepCount + 1, Dt, &predicted);
    return predicted;
}

void ReferenceStaggeredDynamics::kickSolvent(OpenMM::ContextImpl& context, const StaggeredDPDIntegrator& integrator,
                                             const std::vector<Vec3>& newF) {
    std::vector<Vec3>& u = *data(context).velocities;
    const std::vector<Vec3>& F = carried.force;
    const std::vector<double>& invMass = parameters.getInverseMasses();
    const double Dt = integrator.getStepSize();
    for (size_t i = 0; i < u.size(); i++)
        if (!isPolymer((int) i))
            u[i] += (F[i] + newF[i]) * (0.5 * Dt * invMass[i]);
}

void ReferenceStaggeredDynamics::subCycle(OpenMM::ContextImpl& context, const StaggeredDPDIntegrator& integrator,
                                          const StepStart& start, const std::vector<Vec3>& newF) {
    std::vector<Vec3>& r = *data(context).positions;
    std::vector<Vec3>& u = *data(context).velocities;
    const double b = integrator.getB();
    // Under shear the predicting drift slid the box to the end of the step and wrapped the
    // molecules that crossed, the polymer's too, with their velocity jumps.  The polymer
    // starts again from the start of the step, so from that time's box and velocities too;
    // each sub-step's drift slides the box on and wraps the polymer when it crosses.
    Vec3 endBox[3];
    context.getPeriodicBoxVectors(endBox[0], endBox[1], endBox[2]);
    const bool sheared = (parameters.getShearRate() != 0);
    if (sheared)
        context.setPeriodicBoxVectors(start.box[0], start.box[1], start.box[2]);
    // The polymer starts again from r_p, driven by F^^_p = b F_p + (1 - b) F^_p.
    std::vector<Vec3> driving(r.size());
    for (int p : polymer.particles) {
        r[p] = start.positions[p];
        u[p] = start.velocities[p];
        driving[p] = carried.force[p] * b + newF[p] * (1 - b);
    }
    for (int s = 0; s < integrator.getNumSubSteps(); s++)
        subStep(context, integrator, s, driving, newF);
    // K sub-step slides make U Dt up to rounding: the step ends in the box F^ was evaluated in.
    if (sheared)
        context.setPeriodicBoxVectors(endBox[0], endBox[1], endBox[2]);
}

void ReferenceStaggeredDynamics::subStep(OpenMM::ContextImpl& context, const StaggeredDPDIntegrator& integrator, int s,
                                         const std::vector<Vec3>& driving, const std::vector<Vec3>& newF) {
    std::vector<Vec3>& r = *data(context).positions;
    std::vector<Vec3>& u = *data(context).velocities;
    const std::vector<Vec3>& F = carried.force;
    const std::vector<double>& invMass = parameters.getInverseMasses();
    const int K = integrator.getNumSubSteps();
    const double dt = integrator.getStepSize() / K;
    const long long next = data(context).stepCount + 1;
    // r_p <- r_p + dt u_p + dt^2/(2m) (F^^_p + Fp_p)
    std::vector<Vec3> move(r.size());
    for (size_t k = 0; k < polymer.particles.size(); k++) {
        const int p = polymer.particles[k];
        move[p] = u[p] * dt + (driving[p] + Fp[k]) * (0.5 * dt * dt * invMass[p]);
    }
    movePositions(context, move, next, dt);
    // Fp* <- Fp(r_p)
    const std::vector<Vec3> newFp = fastForce(context, integrator, next);
    // The slow force at the two ends of the sub-step, linear in time from F to F^
    // (weighted): Fold = (K-s)/K F + s/K F^, Fnew = (K-s-1)/K F + (s+1)/K F^;
    // or (non-weighted) Fold = F, Fnew = F^.
    const SubStepWeights w(integrator, s);
    // u_p <- u_p + dt/(2m) [(Fold + Fp_p) + (Fnew + Fp*)] ;  Fp_p <- Fp*
    for (size_t k = 0; k < polymer.particles.size(); k++) {
        const int p = polymer.particles[k];
        const Vec3 Fold = F[p] * w.oldOfF + newF[p] * w.oldOfNewF;
        const Vec3 Fnew = F[p] * w.newOfF + newF[p] * w.newOfNewF;
        u[p] += ((Fold + Fp[k]) + (Fnew + newFp[k])) * (0.5 * dt * invMass[p]);
    }
    Fp = newFp;
}

// Symeonidis and Karniadakis 2006, Table 2, after the sub-cycle: "for all N_p distinct pairs
// i, j such that r_ij < r_c (solvent, polymer) ... if w < Gamma Dt: Delta_ij = ... ; u_i <- u_i + Delta_ij,
// u_j <- u_j - Delta_ij", and section 4.2: "The thermalization is done once at the end of the
// Dt cycle".  r_ij there is the unhatted position, which at that point is the corrected one:
// the hatted r^^_p are "provisional values" (section 4.1) used only for the one force
// evaluation, and "the velocity and the position of the polymer are corrected in the
// subsequent loop".  So the pairs, their distances and directions are those at the
// end-of-step positions r_s, r_p -- found here, where they are used.
void ReferenceStaggeredDynamics::thermalise(OpenMM::ContextImpl& context, const StaggeredDPDIntegrator& integrator, long long step) {
    std::vector<Vec3>& u = *data(context).velocities;
    const LowePairUpdate<> collide{integrator.getStepSize(), parameters.getKT(), {parameters.getInverseMasses()}};
    const DrawnBits draw{random, PairRandom::PairThermalisation, step};
    for (const PairGeometry& pair : findPairs(context))
        collide(pair, draw(pair), u);
}

// The CPU platform's layout: the number of polymer particles, then Fp on each.
void ReferenceStaggeredDynamics::saveExtraState(std::ostream& stream) const {
    putVectors(stream, Fp);
}

void ReferenceStaggeredDynamics::loadExtraState(CheckpointReader& reader) {
    loadedFp.resize(Fp.size());
    reader.takeVectors(loadedFp, "the fast force on the polymer particles");
}
