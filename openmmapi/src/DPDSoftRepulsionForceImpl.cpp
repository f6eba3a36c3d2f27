#include "openmmdpd/internal/DPDSoftRepulsionForceImpl.h"
#include "openmmdpd/DPDKernels.h"
#include "openmm/OpenMMException.h"
#include "openmm/internal/ContextImpl.h"
#include <sstream>

using namespace DPDPlugin;
using OpenMM::OpenMMException;

void DPDSoftRepulsionForceImpl::validate(const DPDSoftRepulsionForce& force, const OpenMM::System& system) {
    const int n = system.getNumParticles();
    force.getTypeTable().validate(system, "DPDSoftRepulsionForce");
    for (int k = 0; k < force.getNumExclusions(); k++) {
        int p1, p2;
        force.getExclusionParticles(k, p1, p2);
        if (p1 >= n || p2 >= n)
            throw OpenMMException("DPDSoftRepulsionForce: exclusion " + std::to_string(k) + " names a particle beyond the System's " +
                                  std::to_string(n));
    }
    if (force.usesPeriodicBoundaryConditions()) {
        OpenMM::Vec3 a, b, c;
        system.getDefaultPeriodicBoxVectors(a, b, c);
        const double halfWidth = 0.5 * std::min(a[0], std::min(b[1], c[2]));
        if (force.getMaxCutoff() > halfWidth) {
            std::ostringstream message;
            message << "DPDSoftRepulsionForce: the cutoff (" << force.getMaxCutoff()
                    << " nm) must not exceed half the periodic box width (" << halfWidth << " nm)";
            throw OpenMMException(message.str());
        }
    }
}

void DPDSoftRepulsionForceImpl::initialize(OpenMM::ContextImpl& context) {
    validate(owner, context.getSystem());
    kernel = context.getPlatform().createKernel(CalcDPDSoftRepulsionForceKernel::Name(), context);
    kernel.getAs<CalcDPDSoftRepulsionForceKernel>().initialize(context.getSystem(), owner);
}

double DPDSoftRepulsionForceImpl::calcForcesAndEnergy(OpenMM::ContextImpl& context, bool includeForces, bool includeEnergy, int groups) {
    if ((groups & (1 << owner.getForceGroup())) == 0)
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
