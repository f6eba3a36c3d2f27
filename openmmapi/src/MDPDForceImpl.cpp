#include "openmmdpd/internal/MDPDForceImpl.h"
#include "openmmdpd/DPDKernels.h"
#include "openmmdpd/internal/ParameterChecks.h"
#include "openmm/internal/ContextImpl.h"

using namespace DPDPlugin;

void MDPDForceImpl::validate(const MDPDForce& force, const OpenMM::System& system) {
    const int n = system.getNumParticles();
    force.getTypeTable().validate(system);
    for (int k = 0; k < force.getNumExclusions(); k++) {
        int p1, p2;
        force.getExclusionParticles(k, p1, p2);
        require(p1 < n && p2 < n, "MDPDForce: the particles of exclusion " + std::to_string(k) + " must be < " + std::to_string(n) +
                " (the System's particle count), got " + std::to_string(p1) + ", " + std::to_string(p2));
    }
    if (force.usesPeriodicBoundaryConditions()) {
        OpenMM::Vec3 box[3];
        system.getDefaultPeriodicBoxVectors(box[0], box[1], box[2]);
        requireCutoffFitsBox("MDPDForce", "the cutoff", force.getMaxCutoff(), box);
    }
}

void MDPDForceImpl::initialize(OpenMM::ContextImpl& context) {
    validate(owner, context.getSystem());
    kernel = context.getPlatform().createKernel(CalcMDPDForceKernel::Name(), context);
    kernel.getAs<CalcMDPDForceKernel>().initialize(context.getSystem(), owner);
}

double MDPDForceImpl::calcForcesAndEnergy(OpenMM::ContextImpl& context, bool includeForces, bool includeEnergy, int groups) {
    if ((groups & (1 << owner.getForceGroup())) == 0 || isLeftOut())
        return 0.0;
    return kernel.getAs<CalcMDPDForceKernel>().execute(context, includeForces, includeEnergy);
}

std::vector<std::string> MDPDForceImpl::getKernelNames() {
    return {CalcMDPDForceKernel::Name()};
}

std::array<double, 6> MDPDForceImpl::computeVirial(OpenMM::ContextImpl& context) {
    return kernel.getAs<CalcMDPDForceKernel>().computeVirial(context);
}

void MDPDForceImpl::updateParametersInContext(OpenMM::ContextImpl& context) {
    validate(owner, context.getSystem());
    kernel.getAs<CalcMDPDForceKernel>().copyParametersToContext(context, owner);
    context.systemChanged();
}
