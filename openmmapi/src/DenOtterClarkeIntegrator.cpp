#include "openmmdpd/DenOtterClarkeIntegrator.h"
#include "openmmdpd/DPDKernels.h"
#include "openmmdpd/internal/ParameterChecks.h"
#include "openmm/System.h"
#include <cmath>
#include <string>

using namespace DPDPlugin;

namespace {

const std::string NOT_SET = " (set the averages with setAverageFDDotV/FDDotFD/FRDotFR, e.g. from "
                            "Nikunen et al. 2003, Table III, or measure them with openmmdpd.calibrate_den_otter_clarke)";

} // namespace

DenOtterClarkeIntegrator::DenOtterClarkeIntegrator(double temperature, double defaultFriction, double defaultCutoff,
                                                   double stepSize) :
        DPDThermostatIntegrator("DenOtterClarkeIntegrator", temperature, defaultFriction, defaultCutoff, stepSize) {
}

void DenOtterClarkeIntegrator::setAverageFDDotV(double value) {
    require(std::isfinite(value) && value < 0,
            "DenOtterClarkeIntegrator: averageFDDotV must be < 0 kJ/mol/ps (friction takes energy out), got " + numberText(value));
    fdDotV = value;
}

void DenOtterClarkeIntegrator::setAverageFDDotFD(double value) {
    require(std::isfinite(value) && value > 0,
            "DenOtterClarkeIntegrator: averageFDDotFD must be > 0 (kJ/mol/nm)^2, got " + numberText(value));
    fdDotFD = value;
}

void DenOtterClarkeIntegrator::setAverageFRDotFR(double value) {
    require(std::isfinite(value) && value > 0,
            "DenOtterClarkeIntegrator: averageFRDotFR must be > 0 (kJ/mol/nm)^2 ps, got " + numberText(value));
    frDotFR = value;
}

void DenOtterClarkeIntegrator::getPrefactors(double mass, double& alpha, double& beta) const {
    require(fdDotV != 0 && fdDotFD != 0 && frDotFR != 0, "DenOtterClarkeIntegrator: the averages are not set" + NOT_SET);
    const double kT = BOLTZMANN_KJ_PER_MOL_K * getTemperature();
    require(kT > 0, "DenOtterClarkeIntegrator: temperature must be > 0 K (G = -<FD.v>/(3 kT)), got " +
            numberText(getTemperature()));
    const double dt = getStepSize();
    const double x = -fdDotV / (3 * kT) * dt;  // G dt
    const double a = -std::expm1(-x) / x;
    const double beta2 = (-2 * mass * a * fdDotV - a * a * dt * fdDotFD) / frDotFR;
    require(beta2 > 0, "DenOtterClarkeIntegrator: the step size (" + numberText(dt) + " ps) is too long for the averages: "
            "beta^2 = (-2 m alpha <FD.v> - alpha^2 dt <FD.FD>) / <FR.FR> must be > 0, got " + numberText(beta2));
    alpha = a;
    beta = std::sqrt(beta2);
}

void DenOtterClarkeIntegrator::getMeasuredSums(double& sumFDDotV, double& sumFDDotFD, double& sumFRDotFR, long long& count) const {
    getStepKernel().getAs<const IntegrateDenOtterClarkeStepKernel>().getMeasuredSums(sumFDDotV, sumFDDotFD, sumFRDotFR, count);
}

void DenOtterClarkeIntegrator::validate(const OpenMM::System& system) const {
    DPDThermostatIntegrator::validate(system);
    double mass = 0;
    for (int i = 0; i < system.getNumParticles(); i++) {
        const double m = system.getParticleMass(i);
        require(m == 0 || mass == 0 || m == mass, "DenOtterClarkeIntegrator: every particle with mass must have the same mass "
                "(the prefactors are one pair for all particles), got " + numberText(mass) + " and " + numberText(m) +
                " amu (particle " + std::to_string(i) + ")");
        if (m != 0)
            mass = m;
    }
    double alpha, beta;
    getPrefactors(mass, alpha, beta);
}

std::string DenOtterClarkeIntegrator::kernelName() const {
    return IntegrateDenOtterClarkeStepKernel::Name();
}

void DenOtterClarkeIntegrator::initializeStepKernel(OpenMM::Kernel& kernel, const OpenMM::System& system) const {
    kernel.getAs<IntegrateDenOtterClarkeStepKernel>().initialize(system, *this);
}

void DenOtterClarkeIntegrator::executeStepKernel(OpenMM::Kernel& kernel, OpenMM::ContextImpl& context) const {
    kernel.getAs<IntegrateDenOtterClarkeStepKernel>().execute(context, *this);
}
