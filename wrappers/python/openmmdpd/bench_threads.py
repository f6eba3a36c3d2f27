"""Each integrator's speed-up with threads on model B, and its ceiling.

Default: GW, S1 and Langevin at N = 256000, 1 and 2 threads; each integrator's Contexts at
every thread count timed interleaved in a process of their own. Then, as the ceiling for that
speed-up, as many one-thread copies in processes of their own, all at once against one alone
(bench_copies).

    python3 -m openmmdpd.bench thread-scaling [--sizes 256000] [--threads 1 2]
"""
from concurrent.futures.process import BrokenProcessPool
import sys

from .bench_copies import measure_copies, print_copies_table
from .bench_scale import SCALE_DT, SCALE_SECONDS
from .bench_timing import (add_integrators_argument, add_mode, add_round_arguments, add_system_arguments, best_round,
                           factory, in_fresh_process, measure_repeats, median_ratio, two_places)
from .catalog import FRICTION
from .scenes import soft_scene

THREAD_SCALING_INTEGRATORS = ["GW", "S1", "Langevin"]
THREAD_SCALING_SIZES = [256000]
SUMMARY = ("each integrator's speed-up with threads, and one-thread copies at once as its ceiling "
           "(GW S1 Langevin, N 256000, 1 and 2 threads, 3 rounds: a few minutes)")
DURATION = ("With the defaults a run takes a few minutes on 2 cores; the time grows with the sizes, the "
            "integrators, the thread counts and --repeats.")


def add_parsers(modes):
    parser = add_mode(modes, "thread-scaling", SUMMARY, f"{__doc__.splitlines()[0]} {DURATION}", run)
    parser.set_defaults(platform="CPU")  # the CPU platform's threads are what is measured
    add_system_arguments(parser, THREAD_SCALING_SIZES, [1, 2], SCALE_DT)
    add_integrators_argument(parser, THREAD_SCALING_INTEGRATORS, edpd=True)
    add_round_arguments(parser, SCALE_SECONDS, "interleaved rounds: steps/s the best, speed-ups their medians")


def run(args):
    print_thread_scaling_table(measure_thread_scaling(args.integrators, args), args)
    if max(args.threads) > 1:
        print_copies_table(measure_copies(args.integrators, args), args)


def measure_thread_scaling(names, args):
    """Rows (N, integrator, {threads: best steps/s}, {threads: speed-up}): each integrator's
    Contexts at every thread count interleaved, round by round, in a process of its own; a
    speed-up is the median over the rounds of the round's rate / the first thread count's (a
    busy spell of the shared host slows a whole round, not one Context)."""
    rows = []
    for n in args.sizes:
        for name in names:
            print(f"measuring N={n} {name} threads {' '.join(map(str, args.threads))} ...", file=sys.stderr, flush=True)
            try:
                rates = in_fresh_process(thread_rates, n, name, args)
            except BrokenProcessPool as error:  # killed (memory?)
                rates = {threads: f"failed: {error}" for threads in args.threads}
            first = rates[args.threads[0]]
            rows.append((n, name, {threads: best_round(own) for threads, own in rates.items()},
                         {threads: median_ratio(own, first) for threads, own in rates.items()}))
    return rows


def thread_rates(n, name, args):
    """{threads: steps/s of each round} of integrator `name` on model B with n particles."""
    make = factory(name, args.edpd_alpha)
    return measure_repeats(soft_scene(num_particles=n), [(threads, make, threads) for threads in args.threads], args)


def print_thread_scaling_table(rows, args):
    print(f"scene soft (model B: rho=4, a=25, DPDSoftRepulsionForce), CPU platform, dt={args.dt:g}, "
          f"gamma={FRICTION:g}; each integrator at {', '.join(map(str, args.threads))} threads interleaved, "
          f"{args.repeats} rounds of {args.seconds:g} s blocks; steps/s: best round; speed-up: median over the rounds "
          f"of the round's rate / its rate at {args.threads[0]} thread(s)")
    print(f"{'N':>8}  {'integrator':<10} {'threads':>7} {'steps/s':>9} {'speed-up':>8}")
    for n, name, best, speedup in rows:
        for threads in args.threads:
            rate = best[threads]
            if isinstance(rate, str):
                print(f"{n:>8}  {name:<10} {threads:>7} {rate}")
                continue
            print(f"{n:>8}  {name:<10} {threads:>7} {rate:>9.2f} {two_places(speedup[threads]):>8}")
