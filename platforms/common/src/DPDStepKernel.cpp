#include "openmmdpd/DPDStepKernel.h"
#include "openmmdpd/DPDVVDynamics.h"
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
