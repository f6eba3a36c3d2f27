#ifndef OPENMMDPD_THREADPOOLEXECUTOR_H_
#define OPENMMDPD_THREADPOOLEXECUTOR_H_

#include "openmmdpd/ParallelExecutor.h"
#include "openmm/internal/ThreadPool.h"

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

} // namespace DPDPlugin

#endif
