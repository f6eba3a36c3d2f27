#include "openmmdpd/LoweAndersenIntegrator.h"
#include "openmmdpd/DPDKernels.h"
#include "openmmdpd/internal/ParameterChecks.h"

using namespace DPDPlugin;

LoweAndersenIntegrator::LoweAndersenIntegrator(double temperature, double defaultGamma, double defaultCutoff, double stepSize) :
        DPDThermostatIntegrator("LoweAndersenIntegrator", temperature, defaultGamma, defaultCutoff, stepSize), method(Lowe), splitting(AfterVerlet) {
}

void LoweAndersenIntegrator::setMethod(Method m) {
    require(m == Lowe || m == PairOrnsteinUhlenbeck,
            "LoweAndersenIntegrator: method must be Lowe (0) or PairOrnsteinUhlenbeck (1), got " + std::to_string((int) m));
    method = m;
}

void LoweAndersenIntegrator::setSplitting(Splitting s) {
    require(s == AfterVerlet || s == Middle,
            "LoweAndersenIntegrator: splitting must be AfterVerlet (0) or Middle (1), got " + std::to_string((int) s));
    splitting = s;
}

void LoweAndersenIntegrator::validate(const OpenMM::System& system) const {
    DPDThermostatIntegrator::validate(system);
    // Gamma dt is a probability.
    require(method != Lowe || getMaxFriction() * getStepSize() <= 1,
            "LoweAndersenIntegrator: Gamma dt must be <= 1 (it is a collision probability), got the largest Gamma (" +
            numberText(getMaxFriction()) + " /ps) times the step size (" + numberText(getStepSize()) + " ps) = " +
            numberText(getMaxFriction() * getStepSize()));
}

void LoweAndersenIntegrator::validateTransverseFriction(const OpenMM::System& system) const {
    require(method == PairOrnsteinUhlenbeck, "LoweAndersenIntegrator: transverse friction is available with the "
            "PairOrnsteinUhlenbeck method (1) only: Lowe's collisions redraw the velocity along e alone");
    refuseTransverseFrictionWithConstraints(system);
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
