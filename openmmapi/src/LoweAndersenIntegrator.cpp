#include "openmmdpd/LoweAndersenIntegrator.h"
#include "openmmdpd/DPDKernels.h"
#include "openmm/OpenMMException.h"
#include <sstream>

using namespace DPDPlugin;

LoweAndersenIntegrator::LoweAndersenIntegrator(double temperature, double defaultGamma, double defaultCutoff, double stepSize) :
        DPDThermostatIntegrator(temperature, defaultGamma, defaultCutoff, stepSize), method(Lowe) {
}

void LoweAndersenIntegrator::setMethod(Method m) {
    if (m != Lowe && m != PairOrnsteinUhlenbeck)
        throw OpenMM::OpenMMException("method must be Lowe (0) or PairOrnsteinUhlenbeck (1), got " + std::to_string((int) m));
    method = m;
}

void LoweAndersenIntegrator::validate(const OpenMM::System& system) const {
    DPDThermostatIntegrator::validate(system);
    // Gamma dt is a probability.
    if (method == Lowe && getMaxFriction() * getStepSize() > 1) {
        std::ostringstream message;
        message << "LoweAndersenIntegrator: Gamma dt must be <= 1 (it is a collision probability), but the largest Gamma ("
                << getMaxFriction() << " /ps) times the step size (" << getStepSize() << " ps) is " << getMaxFriction() * getStepSize();
        throw OpenMM::OpenMMException(message.str());
    }
}

std::string LoweAndersenIntegrator::kernelName() const {
    return IntegrateLoweAndersenStepKernel::Name();
}

void LoweAndersenIntegrator::initializeStepKernel(OpenMM::Kernel& kernel, const OpenMM::System& system) const {
    kernel.getAs<IntegrateLoweAndersenStepKernel>().initialize(system, *this);
}

void LoweAndersenIntegrator::executeStepKernel(OpenMM::Kernel& kernel, OpenMM::ContextImpl& context) const {
    kernel.getAs<IntegrateLoweAndersenStepKernel>().execute(context, *this);
}
