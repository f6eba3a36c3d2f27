#include "openmmdpd/internal/DPDSoftRepulsionForceImpl.h"
#include "openmmdpd/DPDKernels.h"
#include "openmm/internal/ContextImpl.h"
#include "openmmdpd/internal/ParameterChecks.h"

using namespace DPDPlugin;

void DPDSoftRepulsionForceImpl::validate(const DPDSoftRepulsionForce& force, const OpenMM::System& system) {
    const int n = system.getNumParticles();
    force.getTypeTable().validate(system);
    for (int k = 0; k < force.getNumExclusions(); k++) {
        int p1, p2;
        force.getExclusionParticles(k, p1, p2);
        require(p1 < n && p2 < n, "DPDSoftRepulsionForce: the particles of exclusion " + std::to_string(k) + " must be < " +
                std::to_string(n) + " (the System's particle count), got " + std::to_string(p1) + ", " + std::to_string(p2));
    }
    if (force.usesPeriodicBoundaryConditions()) {
        OpenMM::Vec3 box[3];
        system.getDefaultPeriodicBoxVectors(box[0], box[1], box[2]);
        requireCutoffFitsBox("DPDSoftRepulsionForce", "the cutoff", force.getMaxCutoff(), box);
    }
}

void DPDSoftRepulsionForceImpl::initialize(OpenMM::ContextImpl& context) {
    validate(owner, context.getSystem());
    kernel = context.getPlatform().createKernel(CalcDPDSoftRepulsionForceKernel::Name(), context);
    kernel.getAs<CalcDPDSoftRepulsionForceKernel>().initialize(context.getSystem(), owner);
}

double DPDSoftRepulsionForceImpl::calcForcesAndEnergy(OpenMM::ContextImpl& context, bool includeForces, bool includeEnergy, int groups) {
    if ((groups & (1 << owner.getForceGroup())) == 0 || isLeftOut())
        return 0.0;
    return kernel.getAs<CalcDPDSoftRepulsionForceKernel>().execute(context, includeForces, includeEnergy);
}

std::vector<std::string> DPDSoftRepulsionForceImpl::getKernelNames() {
    return {CalcDPDSoftRepulsionForceKernel::Name()};
}

void DPDSoftRepulsionForceImpl::updateParametersInContext(OpenMM::ContextImpl& context) {
    validate(owner, context.getSystem());
    kernel.getAs<CalcDPDSoftRepulsionForceKernel>().copyParametersToContext(context, owner);
    context.systemChanged();
}

std::array<double, 6> DPDSoftRepulsionForceImpl::computeVirial(OpenMM::ContextImpl& context) {
    return kernel.getAs<CalcDPDSoftRepulsionForceKernel>().computeVirial(context);
}
