#ifndef OPENMMDPD_DYNAMICSSTEPKERNEL_H_
#define OPENMMDPD_DYNAMICSSTEPKERNEL_H_

#include "openmmdpd/CheckpointIO.h"
#include "openmmdpd/CheckpointTags.h"
#include "openmmdpd/DPDKernels.h"
#include "openmmdpd/PairRandom.h"
#include "openmmdpd/PressureTensor.h"
#include "openmmdpd/StepState.h"
#include "openmm/OpenMMException.h"
#include "openmm/internal/ContextImpl.h"
#include <memory>
#include <sstream>

namespace DPDPlugin {

/**
 * A step kernel of the typed interface Interface of Integrator, run by a platform's
 * Dynamics (its update rule): what every platform's kernels share.  Thermostat parameters
 * changed on a live Context, and a new random number seed, reach the Dynamics before the
 * next step.  A platform says how to make its Dynamics.
 *
 * Checkpoints carry a header (CheckpointIO.h) tagged with the integrator's class and
 * variant.  OpenMM restores positions, velocities, step count and time before the
 * integrator reads its part; when that part is refused, the Dynamics drops everything it
 * carried and re-derives it from the Context's current state at the next step, as a new
 * Context would.
 */
template <class Interface, class Integrator, class Dynamics>
class DynamicsStepKernel : public Interface {
public:
    DynamicsStepKernel(std::string name, const OpenMM::Platform& platform) : Interface(name, platform) {}
    void initialize(const OpenMM::System& system, const Integrator& integrator) override {
        dynamics.reset(createDynamics(system, integrator));
        owner = &integrator;
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
        const bool samplePressure = integrator.getPressureTensorEnabled();
        if (samplePressure && !pressure)
            pressure.reset(new PressureTensorSampler(context.getSystem(), integrator.className()));
        SymmetricTensor thermostatVirial{};
        dynamics->recordThermostatVirial(samplePressure ? &thermostatVirial : nullptr);
        stepKeepingTheClock(context, integrator);
        if (samplePressure)
            pressure->addSample(context, integrator.getShearRate(), integrator.getIntegrationForceGroups(), thermostatVirial,
                                dynamics->positionStrain());
    }
    std::vector<double> getAveragePressureTensor(int part) const override {
        if (getPressureTensorSampleCount() == 0)
            throw OpenMM::OpenMMException(std::string(owner->className()) +
                                          ": no step has sampled the pressure tensor since it was last reset "
                                          "(setPressureTensorEnabled(true), then step)");
        return pressure->average(part);
    }
    long long getPressureTensorSampleCount() const override { return pressure ? pressure->getCount() : 0; }
    void resetPressureTensor() override {
        if (pressure)
            pressure->reset();
    }
    double computeKineticEnergy(OpenMM::ContextImpl& context) override { return dynamics->computeKineticEnergy(context); }
    void invalidateForces() override { dynamics->invalidateForces(); }
    void createCheckpoint(OpenMM::ContextImpl& context, std::ostream& stream) const override {
        std::ostringstream payload;
        // The pressure tensor's average goes with the run it was sampled in.
        writePressureSums(payload, pressure.get());
        dynamics->createCheckpoint(payload);
        writeCheckpoint(stream, checkpointTag(*owner), context.getSystem().getNumParticles(), payload.str());
    }
    void loadCheckpoint(OpenMM::ContextImpl& context, std::istream& stream) override {
        const std::string tag = checkpointTag(*owner);
        try {
            CheckpointReader reader = readCheckpoint(stream, tag, context.getSystem().getNumParticles(), tag.substr(0, tag.find(' ')));
            const PressureSums sums = readPressureSums(reader);
            std::unique_ptr<PressureTensorSampler> loadedPressure;
            if (sums.count > 0) {
                loadedPressure.reset(new PressureTensorSampler(context.getSystem(), owner->className()));
                loadedPressure->setSums(sums);
            }
            dynamics->loadCheckpoint(context, reader);
            pressure = std::move(loadedPressure);
        }
        catch (...) {
            dynamics->resetState();
            throw;
        }
    }

protected:
    /** One step; a stopped step (StepStopped) leaves the Context's time and step count at the step it stopped in. */
    void stepKeepingTheClock(OpenMM::ContextImpl& context, const Integrator& integrator) {
        const long long stepCount = context.getStepCount();
        const double time = context.getTime();
        try {
            dynamics->step(context, integrator);
        }
        catch (const StepStopped&) {
            if (context.getStepCount() == stepCount) {
                context.setStepCount(stepCount + 1);
                context.setTime(time + integrator.getStepSize());
            }
            throw;
        }
    }
    virtual Dynamics* createDynamics(const OpenMM::System& system, const Integrator& integrator) = 0;
    std::unique_ptr<Dynamics> dynamics;
    std::unique_ptr<PressureTensorSampler> pressure;  // made when the integrator first asks for it
    const Integrator* owner = nullptr;
    int parametersVersion = 0, seedVersion = 0;
};

/** A den Otter-Clarke step kernel of any platform: it answers from its Dynamics' sums (getSums()). */
template <class StepKernel>
class MeasuringStepKernel : public StepKernel {
public:
    using StepKernel::StepKernel;
    void getMeasuredSums(double& sumFDDotV, double& sumFDDotFD, double& sumFRDotFR, long long& count) const override {
        this->dynamics->getSums().get(sumFDDotV, sumFDDotFD, sumFRDotFR, count);
    }
};

} // namespace DPDPlugin

#endif
