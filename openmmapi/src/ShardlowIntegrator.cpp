#include "openmmdpd/ShardlowIntegrator.h"
#include "openmmdpd/DPDKernels.h"
#include "openmmdpd/internal/ParameterChecks.h"

using namespace DPDPlugin;

ShardlowIntegrator::ShardlowIntegrator(double temperature, double defaultFriction, double defaultCutoff, double stepSize) :
        DPDThermostatIntegrator("ShardlowIntegrator", temperature, defaultFriction, defaultCutoff, stepSize), order(1) {
}

void ShardlowIntegrator::setOrder(int value) {
    require(value == 1 || value == 2, "ShardlowIntegrator: order must be 1 (S1) or 2 (S2), got " + std::to_string(value));
    order = value;
}

std::string ShardlowIntegrator::kernelName() const {
    return IntegrateShardlowStepKernel::Name();
}

void ShardlowIntegrator::initializeStepKernel(OpenMM::Kernel& kernel, const OpenMM::System& system) const {
    kernel.getAs<IntegrateShardlowStepKernel>().initialize(system, *this);
}

void ShardlowIntegrator::executeStepKernel(OpenMM::Kernel& kernel, OpenMM::ContextImpl& context) const {
    kernel.getAs<IntegrateShardlowStepKernel>().execute(context, *this);
}
