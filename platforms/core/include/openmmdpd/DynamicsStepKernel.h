#ifndef OPENMMDPD_DYNAMICSSTEPKERNEL_H_
#define OPENMMDPD_DYNAMICSSTEPKERNEL_H_

#include "openmmdpd/DPDKernels.h"
#include "openmmdpd/PairRandom.h"
#include <memory>

namespace DPDPlugin {

/**
 * A step kernel of the typed interface Interface of Integrator, run by a platform's
 * Dynamics (its update rule): what every platform's kernels share.  Thermostat parameters
 * changed on a live Context, and a new random number seed, reach the Dynamics before the
 * next step.  A platform says how to make its Dynamics.
 */
template <class Interface, class Integrator, class Dynamics>
class DynamicsStepKernel : public Interface {
public:
    DynamicsStepKernel(std::string name, const OpenMM::Platform& platform) : Interface(name, platform) {}
    void initialize(const OpenMM::System& system, const Integrator& integrator) override {
        dynamics.reset(createDynamics(system, integrator));
        parametersVersion = integrator.getThermostatParametersVersion();
        seedVersion = integrator.getRandomNumberSeedVersion();
    }
    void execute(OpenMM::ContextImpl& context, const Integrator& integrator) override {
        if (integrator.getThermostatParametersVersion() != parametersVersion) {
            dynamics->updateParameters(context.getSystem(), integrator);
            parametersVersion = integrator.getThermostatParametersVersion();
        }
        // Only a new setting reseeds: a seed restored from a checkpoint stays otherwise.
        if (integrator.getRandomNumberSeedVersion() != seedVersion) {
            dynamics->setSeed(PairRandom::seedFor(integrator.getRandomNumberSeed()));
            seedVersion = integrator.getRandomNumberSeedVersion();
        }
        dynamics->step(context, integrator);
    }
    double computeKineticEnergy(OpenMM::ContextImpl& context) override { return dynamics->computeKineticEnergy(context); }
    void invalidateForces() override { dynamics->invalidateForces(); }
    void createCheckpoint(OpenMM::ContextImpl&, std::ostream& stream) const override { dynamics->createCheckpoint(stream); }
    void loadCheckpoint(OpenMM::ContextImpl& context, std::istream& stream) override { dynamics->loadCheckpoint(context, stream); }

protected:
    virtual Dynamics* createDynamics(const OpenMM::System& system, const Integrator& integrator) = 0;
    std::unique_ptr<Dynamics> dynamics;
    int parametersVersion = 0, seedVersion = 0;
};

} // namespace DPDPlugin

#endif
