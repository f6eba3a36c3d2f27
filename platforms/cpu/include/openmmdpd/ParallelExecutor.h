#ifndef OPENMMDPD_PARALLELEXECUTOR_H_
#define OPENMMDPD_PARALLELEXECUTOR_H_

#include <cstddef>
#include <functional>

namespace DPDPlugin {

/**
 * Runs a task once per worker.  The Reference platform has one worker that runs in the
 * calling thread; the CPU platform runs its workers on OpenMM's ThreadPool.  Work is
 * split by fixed index ranges (see range()), never by whichever thread is free first.
 */
class ParallelExecutor {
public:
    virtual ~ParallelExecutor() {}
    virtual int getNumWorkers() const = 0;
    /** Run task(worker) for every worker and wait for all of them. */
    virtual void execute(const std::function<void(int worker)>& task) = 0;
    /**
     * Run task(worker, phase) for phase = 0 .. phases-1, every worker finishing a phase
     * (and seeing all its writes) before any starts the next.  Same as one execute() per
     * phase, which is what this default does; a thread pool can do it with one dispatch.
     */
    virtual void executePhases(int phases, const std::function<void(int worker, int phase)>& task) {
        for (int phase = 0; phase < phases; phase++)
            execute([&](int w) { task(w, phase); });
    }
    /**
     * Element-wise loops over fewer items than this run in the calling thread: waking the
     * thread pool (tens of microseconds on a virtual machine) costs more than the loop.
     */
    static constexpr size_t SERIAL_LOOP_LIMIT = 16384;
    /**
     * body(w, begin, end) for each worker w's range of [0, n) when n is large enough to pay
     * for it, else body(0, 0, n) alone in the calling thread.
     */
    template <class Body>
    void forEachRange(size_t n, Body body) {
        if (n < SERIAL_LOOP_LIMIT) {
            body(0, (size_t) 0, n);
            return;
        }
        execute([&](int w) {
            size_t begin, end;
            range(w, n, begin, end);
            body(w, begin, end);
        });
    }
    /** body(i) for i in [0, n), over the workers when n is large enough to pay for it. */
    template <class Body>
    void forEach(size_t n, Body body) {
        forEachRange(n, [&](int, size_t begin, size_t end) {
            for (size_t i = begin; i < end; i++)
                body(i);
        });
    }
    /** The half-open range [begin, end) of n items that a worker handles. */
    void range(int worker, size_t n, size_t& begin, size_t& end) const {
        const size_t w = getNumWorkers();
        begin = n * worker / w;
        end = n * (worker + 1) / w;
    }
};

/** One worker, in the calling thread. */
class SerialExecutor : public ParallelExecutor {
public:
    int getNumWorkers() const override { return 1; }
    void execute(const std::function<void(int worker)>& task) override { task(0); }
};

} // namespace DPDPlugin

#endif
