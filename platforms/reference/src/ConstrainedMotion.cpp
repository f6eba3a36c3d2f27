#include "openmmdpd/ConstrainedMotion.h"
#include "openmm/Integrator.h"
#include "openmm/System.h"
#include "ReferenceConstraints.h"
#include "ReferencePlatform.h"

using namespace DPDPlugin;
using OpenMM::Vec3;

namespace {

OpenMM::ReferencePlatform::PlatformData& platformData(OpenMM::ContextImpl& context) {
    return *static_cast<OpenMM::ReferencePlatform::PlatformData*>(context.getPlatformData());
}

} // namespace

ConstrainedMotion::ConstrainedMotion(const OpenMM::System& system) :
        inverseMasses(system.getNumParticles()), constraints(system.getNumConstraints() > 0), sites(false) {
    for (int i = 0; i < system.getNumParticles(); i++) {
        const double mass = system.getParticleMass(i);
        inverseMasses[i] = (mass > 0 ? 1 / mass : 0);
        sites = sites || system.isVirtualSite(i);
    }
}

void ConstrainedMotion::startDrift(const std::vector<Vec3>& positions) {
    if (constraints)
        oldPositions = positions;
}

void ConstrainedMotion::finishDrift(OpenMM::ContextImpl& context, double dt, std::vector<Vec3>* alsoCorrect) {
    if (constraints) {
        OpenMM::ReferencePlatform::PlatformData& data = platformData(context);
        std::vector<Vec3>& r = *data.positions;
        std::vector<Vec3>& v = *data.velocities;
        unconstrained = r;
        data.constraints->apply(oldPositions, r, inverseMasses, context.getIntegrator().getConstraintTolerance());
        for (size_t i = 0; i < r.size(); i++) {
            if (inverseMasses[i] == 0)
                continue;
            const Vec3 correction = (r[i] - unconstrained[i]) * (1 / dt);
            v[i] += correction;
            if (alsoCorrect != nullptr)
                (*alsoCorrect)[i] += correction;
        }
    }
    if (sites)
        context.computeVirtualSites();
}

void ConstrainedMotion::constrainVelocities(OpenMM::ContextImpl& context) {
    if (!constraints)
        return;
    OpenMM::ReferencePlatform::PlatformData& data = platformData(context);
    data.constraints->applyToVelocities(*data.positions, *data.velocities, inverseMasses,
                                        context.getIntegrator().getConstraintTolerance());
}
