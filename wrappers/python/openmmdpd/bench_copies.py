"""The ceiling for thread-scaling's speed-up: as many one-thread copies of an integrator as the
most threads, in processes of their own, their steps/s summed while all run, against one copy
alone. Copies share no memory and never wait for each other, so what the threads fall short of
it is the code's, not the machine's."""
import multiprocessing
import queue
import sys
import threading
import time

from .bench_timing import factory, median_ratio, started_context, two_places, warm_up
from .scenes import soft_scene

COPY_TIMEOUT = 600.0  # s: the longest one copy may wait for the others (their setup at a million particles included)
# What a copy reports when the barrier broke under it: another copy stopped (its own error says
# why) or never came.
BROKEN_BARRIER = "failed: another copy stopped"


def measure_copies(names, args):
    """Rows (N, integrator, copies, speed-up): the median over the rounds, alternated, of the
    copies' summed steps/s at once / one copy's alone."""
    copies = max(args.threads)
    rows = []
    for n in args.sizes:
        for name in names:
            print(f"measuring N={n} {name} {copies} one-thread copies ...", file=sys.stderr, flush=True)
            rows.append((n, name, copies, copies_speedup(n, name, copies, args)))
    return rows


def copies_speedup(n, name, copies, args):
    """The median over rounds of the copies' summed steps/s at once / copy 0's alone, or the error."""
    return combine_copy_rounds(run_copies(n, name, copies, args), copies)


def run_copies(n, name, copies, args):
    """{index: copy_rounds's result} of the copies that reported."""
    context = multiprocessing.get_context("spawn")
    barrier, results = context.Barrier(copies), context.Queue()
    processes = [context.Process(target=copy_rounds, args=(n, name, index, barrier, results, args)) for index in range(copies)]
    for process in processes:
        process.start()
    rounds = {}
    try:
        for _ in processes:
            index, result = results.get(timeout=COPY_TIMEOUT)
            rounds[index] = result
    except queue.Empty:
        pass
    for process in processes:
        process.join(timeout=COPY_TIMEOUT)
        if process.is_alive():
            process.kill()
    return rounds


def combine_copy_rounds(rounds, copies):
    """copies_speedup from each copy's ([steps/s alone], [steps/s at once]) (alone: copy 0's only), or the error."""
    # The copy that stopped first reports why; the others only that the barrier broke, and may
    # report before it, so its error goes first.
    failed = sorted((result for result in rounds.values() if isinstance(result, str)),
                    key=lambda result: result == BROKEN_BARRIER)
    if failed or len(rounds) < copies:
        return failed[0] if failed else "failed: a copy stopped"
    alone = rounds[0][0]
    together = [sum(rounds[index][1][k] for index in range(copies)) for k in range(len(alone))]
    return median_ratio(together, alone)


def copy_rounds(n, name, index, barrier, results, args):
    """Copy `index` of copies_speedup: a one-thread Context of `name` on model B; each round, a
    block of copy 0 alone while the others wait, then a block of every copy at once.  Puts
    (index, ([steps/s alone], [steps/s at once])), or (index, the error)."""
    try:
        context = started_context(soft_scene(num_particles=n), factory(name, args.edpd_alpha), 1, args)
        integrator = context.getIntegrator()
        warm_up(integrator, args)
        alone, together = [], []
        for _ in range(args.repeats):
            barrier.wait(COPY_TIMEOUT)
            if index == 0:
                alone.append(steps_for_seconds(integrator, args.seconds))
            barrier.wait(COPY_TIMEOUT)
            together.append(steps_for_seconds(integrator, args.seconds))
        results.put((index, (alone, together)))
    except threading.BrokenBarrierError:
        results.put((index, BROKEN_BARRIER))
    except Exception as error:  # noqa: BLE001
        # Whatever stops this copy (an OpenMM error, a bug, no memory in Python) must break the
        # barrier: the other copies would otherwise wait at it COPY_TIMEOUT each.  Its error is
        # what the table shows for the copies.
        barrier.abort()
        results.put((index, f"failed: {type(error).__name__}: {error}"))


def steps_for_seconds(integrator, seconds):
    """Steps/s over steps taken one at a time until `seconds` have passed: copies that start
    together are then timed over the same spell, however their speeds differ."""
    steps, start = 0, time.perf_counter()
    while steps == 0 or time.perf_counter() - start < seconds:
        integrator.step(1)
        steps += 1
    return steps / (time.perf_counter() - start)


def print_copies_table(rows, args):
    print(f"one-thread copies in processes of their own, alone and all at once, alternated, {args.repeats} rounds of "
          f"{args.seconds:g} s blocks; speed-up: median over the rounds of the copies' summed steps/s / one copy's "
          f"alone (what the host gives work that shares nothing: the threads' ceiling)")
    print(f"{'N':>8}  {'integrator':<10} {'copies':>7} {'speed-up':>8}")
    for n, name, copies, speedup in rows:
        print(f"{n:>8}  {name:<10} {copies:>7} {two_places(speedup) if not isinstance(speedup, str) else speedup:>8}")
