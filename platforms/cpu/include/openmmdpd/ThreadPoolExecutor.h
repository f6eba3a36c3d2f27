#ifndef OPENMMDPD_THREADPOOLEXECUTOR_H_
#define OPENMMDPD_THREADPOOLEXECUTOR_H_

#include "openmmdpd/ParallelExecutor.h"
#include "openmm/internal/ThreadPool.h"
#include <atomic>
#include <thread>

namespace DPDPlugin {

/** Runs the workers on the CPU platform's own ThreadPool (its thread count). */
class ThreadPoolExecutor : public ParallelExecutor {
public:
    explicit ThreadPoolExecutor(OpenMM::ThreadPool& pool) : pool(pool) {}
    int getNumWorkers() const override { return pool.getNumThreads(); }
    void execute(const std::function<void(int worker)>& task) override {
        // One worker runs in the calling thread: waking a pool thread and waiting for it
        // costs a few microseconds per call, several times per step.
        if (pool.getNumThreads() == 1) {
            task(0);
            return;
        }
        pool.execute([&task](OpenMM::ThreadPool&, int thread) { task(thread); });
        pool.waitForThreads();
    }
    /**
     * One dispatch for all phases, the workers meeting at a spinning barrier between them:
     * waking the pool costs tens of microseconds, which at 27 colours per sweep was most
     * of a small system's sweep.
     */
    void executePhases(int phases, const std::function<void(int worker, int phase)>& task) override {
        const int workers = getNumWorkers();
        if (workers == 1) {
            for (int phase = 0; phase < phases; phase++)
                task(0, phase);
            return;
        }
        std::atomic<int> arrived(0), generation(0);
        pool.execute([&](OpenMM::ThreadPool&, int thread) {
            for (int phase = 0; phase < phases; phase++) {
                task(thread, phase);
                if (phase + 1 == phases)
                    break;
                // The last to arrive opens the next phase; release/acquire make every
                // worker's writes of this phase visible to all in the next.
                const int current = generation.load(std::memory_order_acquire);
                if (arrived.fetch_add(1, std::memory_order_acq_rel) == workers - 1) {
                    arrived.store(0, std::memory_order_relaxed);
                    generation.fetch_add(1, std::memory_order_release);
                }
                else
                    for (int spins = 0; generation.load(std::memory_order_acquire) == current; spins++)
                        if (spins > 1000)
                            std::this_thread::yield();
            }
        });
        pool.waitForThreads();
    }

private:
    OpenMM::ThreadPool& pool;
};

} // namespace DPDPlugin

#endif
