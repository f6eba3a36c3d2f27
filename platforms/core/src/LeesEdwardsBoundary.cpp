#include "openmmdpd/LeesEdwardsBoundary.h"
#include "openmmdpd/internal/ForceTerms.h"
#include "openmm/System.h"
#include <cmath>

using namespace DPDPlugin;
using OpenMM::Vec3;

LeesEdwardsBoundary::LeesEdwardsBoundary(const OpenMM::System& system) :
        moves(system.getNumParticles()), molecules(findMolecules(system)) {
    for (int i = 0; i < system.getNumParticles(); i++)
        moves[i] = (system.getParticleMass(i) != 0);
}

double LeesEdwardsBoundary::advanceOffset(Vec3* box, double rate, double dt) {
    const double Lx = box[0][0], U = rate * box[1][1];
    const double offset = box[1][0] + U * dt;
    box[1][0] = offset - Lx * std::round(offset / Lx);
    return U;
}

void LeesEdwardsBoundary::slide(OpenMM::ContextImpl& context, double rate, double dt, std::vector<Vec3>& positions,
                                std::vector<Vec3>& velocities, std::vector<Vec3>* alsoJump) const {
    if (rate == 0)
        return;
    Vec3 box[3];
    context.getPeriodicBoxVectors(box[0], box[1], box[2]);
    const double Ly = box[1][1], U = advanceOffset(box, rate, dt);
    context.setPeriodicBoxVectors(box[0], box[1], box[2]);
    // A fluid of free particles (the usual DPD system): one pass over them.
    if (molecules.size() == positions.size()) {
        for (size_t i = 0; i < positions.size(); i++) {
            const double crossings = std::floor(positions[i][1] / Ly);
            if (crossings != 0)
                wrap((int) i, crossings, box[1], U, positions, velocities, alsoJump);
        }
        return;
    }
    for (const std::vector<int>& molecule : molecules) {
        double y = 0;
        for (int i : molecule)
            y += positions[i][1];
        const double crossings = std::floor(y / molecule.size() / Ly);
        if (crossings == 0)
            continue;
        for (int i : molecule)
            wrap(i, crossings, box[1], U, positions, velocities, alsoJump);
    }
}

void LeesEdwardsBoundary::wrap(int i, double crossings, const Vec3& b, double U, std::vector<Vec3>& positions,
                               std::vector<Vec3>& velocities, std::vector<Vec3>* alsoJump) const {
    positions[i] -= b * crossings;
    if (!moves[i])
        return;
    velocities[i][0] -= crossings * U;
    if (alsoJump != nullptr)
        (*alsoJump)[i][0] -= crossings * U;
}
