#ifndef OPENMMDPD_CPUDPDKERNELS_H_
#define OPENMMDPD_CPUDPDKERNELS_H_

#include "openmmdpd/DPDKernels.h"
#include "openmmdpd/DPDVVDynamics.h"
#include "openmm/internal/ThreadPool.h"
#include <memory>

namespace DPDPlugin {

/** Runs the workers on the CPU platform's own ThreadPool (its thread count). */
class ThreadPoolExecutor : public ParallelExecutor {
public:
    explicit ThreadPoolExecutor(OpenMM::ThreadPool& pool) : pool(pool) {}
    int getNumWorkers() const override { return pool.getNumThreads(); }
    void execute(const std::function<void(int worker)>& task) override {
        pool.execute([&task](OpenMM::ThreadPool&, int thread) { task(thread); });
        pool.waitForThreads();
    }

private:
    OpenMM::ThreadPool& pool;
};

/** The CPU platform's DPD-VV step: the common update rule over the thread pool. */
class CpuIntegrateDPDVVStepKernel : public IntegrateDPDVVStepKernel {
public:
    CpuIntegrateDPDVVStepKernel(std::string name, const OpenMM::Platform& platform, OpenMM::ContextImpl& context);
    void initialize(const OpenMM::System& system, const DPDVVIntegrator& integrator) override {
        dynamics.reset(new DPDVVDynamics(system, integrator, executor, DEFAULT_PAIR_SKIN));
    }
    void execute(OpenMM::ContextImpl& context, const DPDVVIntegrator& integrator) override { dynamics->step(context, integrator); }
    double computeKineticEnergy(OpenMM::ContextImpl& context, const DPDVVIntegrator& integrator) override {
        return dynamics->computeKineticEnergy(context);
    }
    void invalidateForces() override { dynamics->invalidateForces(); }
    void createCheckpoint(OpenMM::ContextImpl& context, std::ostream& stream) const override { dynamics->createCheckpoint(stream); }
    void loadCheckpoint(OpenMM::ContextImpl& context, std::istream& stream) override { dynamics->loadCheckpoint(context, stream); }

private:
    ThreadPoolExecutor executor;
    std::unique_ptr<DPDVVDynamics> dynamics;
};

} // namespace DPDPlugin

#endif
