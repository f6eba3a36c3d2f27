#include "openmmdpd/DPDStepKernel.h"
#include "openmmdpd/DPDVVDynamics.h"
#include "openmmdpd/EDPDDynamics.h"
#include "openmmdpd/SoftRepulsionKernel.h"
#include "openmmdpd/StaggeredDynamics.h"
#include "openmmdpd/SweepDynamics.h"

using namespace DPDPlugin;

void DPDStepKernel::initialize(const OpenMM::System& system, const DPDThermostatIntegrator& integrator) {
    if (getName() == DPDVVName())
        dynamics.reset(new DPDVVDynamics(system, static_cast<const DPDVVIntegrator&>(integrator), *executor));
    else if (getName() == StaggeredName())
        dynamics.reset(new StaggeredDynamics(system, static_cast<const StaggeredDPDIntegrator&>(integrator), *executor));
    else
        dynamics.reset(new SweepDynamics(system, integrator, *executor));
}

void EDPDStepKernel::initialize(const OpenMM::System& system, const DPDThermostatIntegrator& integrator) {
    dynamics.reset(new EDPDDynamics(system, static_cast<const EDPDIntegrator&>(integrator), *executor));
}

bool EDPDStepKernel::getPairVariable(int i, int j, double& value, long long& step) const {
    return static_cast<const EDPDDynamics&>(*dynamics).getMemory().find(i, j, value, step);
}

long long EDPDStepKernel::getNumPairVariables() const {
    return static_cast<const EDPDDynamics&>(*dynamics).getMemory().size();
}

std::vector<std::string> DPDPlugin::dpdKernelNames() {
    std::vector<std::string> names = DPDStepKernel::names();
    names.push_back(IntegrateEDPDStepKernel::Name());
    names.push_back(CalcDPDSoftRepulsionForceKernel::Name());
    return names;
}

OpenMM::KernelImpl* DPDPlugin::createDPDKernel(const std::string& name, const OpenMM::Platform& platform,
                                               const std::function<std::unique_ptr<ParallelExecutor>()>& makeExecutor) {
    for (const std::string& known : DPDStepKernel::names())
        if (name == known)
            return new DPDStepKernel(name, platform, makeExecutor());
    if (name == IntegrateEDPDStepKernel::Name())
        return new EDPDStepKernel(name, platform, makeExecutor());
    if (name == CalcDPDSoftRepulsionForceKernel::Name())
        return new SoftRepulsionKernel(name, platform, makeExecutor());
    return nullptr;
}
