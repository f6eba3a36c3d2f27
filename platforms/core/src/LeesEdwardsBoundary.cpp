#include "openmmdpd/LeesEdwardsBoundary.h"
#include "openmm/System.h"
#include <cmath>

using namespace DPDPlugin;
using OpenMM::Vec3;

LeesEdwardsBoundary::LeesEdwardsBoundary(const OpenMM::System& system) : moves(system.getNumParticles()) {
    for (int i = 0; i < system.getNumParticles(); i++)
        moves[i] = (system.getParticleMass(i) != 0);
}

void LeesEdwardsBoundary::slide(OpenMM::ContextImpl& context, double rate, double dt, std::vector<Vec3>& positions,
                                std::vector<Vec3>& velocities, std::vector<Vec3>* alsoJump) const {
    if (rate == 0)
        return;
    Vec3 box[3];
    context.getPeriodicBoxVectors(box[0], box[1], box[2]);
    const double Lx = box[0][0], Ly = box[1][1], U = rate * Ly;
    // OpenMM's reduced form needs |offset| <= Lx/2; b and b - a give the same lattice.
    const double offset = box[1][0] + U * dt;
    box[1][0] = offset - Lx * std::round(offset / Lx);
    context.setPeriodicBoxVectors(box[0], box[1], box[2]);
    for (const std::vector<int>& molecule : context.getMolecules()) {
        double y = 0;
        for (int i : molecule)
            y += positions[i][1];
        const double crossings = std::floor(y / molecule.size() / Ly);
        if (crossings == 0)
            continue;
        for (int i : molecule) {
            positions[i] -= box[1] * crossings;
            if (!moves[i])
                continue;
            velocities[i][0] -= crossings * U;
            if (alsoJump != nullptr)
                (*alsoJump)[i][0] -= crossings * U;
        }
    }
}
