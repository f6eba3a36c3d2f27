#include "openmmdpd/LoweAndersenIntegrator.h"
#include "openmmdpd/DPDKernels.h"
#include "openmmdpd/internal/ParameterChecks.h"

using namespace DPDPlugin;

LoweAndersenIntegrator::LoweAndersenIntegrator(double temperature, double defaultGamma, double defaultCutoff, double stepSize) :
        DPDThermostatIntegrator("LoweAndersenIntegrator", temperature, defaultGamma, defaultCutoff, stepSize), method(Lowe) {
}

void LoweAndersenIntegrator::setMethod(Method m) {
    require(m == Lowe || m == PairOrnsteinUhlenbeck,
            "LoweAndersenIntegrator: method must be Lowe (0) or PairOrnsteinUhlenbeck (1), got " + std::to_string((int) m));
    method = m;
}

void LoweAndersenIntegrator::validate(const OpenMM::System& system) const {
    DPDThermostatIntegrator::validate(system);
    // A Lowe collision redraws the pair's relative velocity from N(0, kT/mu) of two free
    // particles; in a constrained System the pair's effective mass differs and the projection
    // that follows cools the system (measured <kT> = 0.88 on a fluid of rigid dimers).
    require(method != Lowe || system.getNumConstraints() == 0,
            "LoweAndersenIntegrator: the Lowe method does not support constraints (the System has " +
            std::to_string(system.getNumConstraints()) + "); use the PairOrnsteinUhlenbeck method, ShardlowIntegrator or "
            "DPDVVIntegrator");
    // Gamma dt is a probability.
    require(method != Lowe || getMaxFriction() * getStepSize() <= 1,
            "LoweAndersenIntegrator: Gamma dt must be <= 1 (it is a collision probability), got the largest Gamma (" +
            numberText(getMaxFriction()) + " /ps) times the step size (" + numberText(getStepSize()) + " ps) = " +
            numberText(getMaxFriction() * getStepSize()));
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
