"""Particle-steps per second from 4000 to a million particles on model B.

dt 0.05, one thread unless --threads says otherwise; each integrator against GW and Langevin at
the same N (timed interleaved with the two, three Contexts at a time, each group in a fresh
process) and against itself at the first N. --platform OpenCL or CUDA measures on that platform
instead of the CPU's (its default precision; --threads does not apply); the sizes are then
32000, 256000 and a million, the integrators GW, S1, Lowe, Langevin and, on OpenMM >= 8.3,
OpenMM's DPDIntegrator.

    python3 -m openmmdpd.bench scale [--sizes 4000 32000 256000 1000000]
    python3 -m openmmdpd.bench scale --platform OpenCL
"""
from concurrent.futures.process import BrokenProcessPool
import sys

import openmm

from .bench_timing import (add_integrators_argument, add_mode, add_platform_argument, add_round_arguments,
                           add_system_arguments, best_round, factory, in_fresh_process, joined, measure_repeats,
                           median_ratio, ratio, two_places)
from .catalog import FRICTION
from .scenes import soft_scene

SCALE_INTEGRATORS = ["GW", "DPD-VV", "S1", "Lowe", "Langevin"]
SCALE_SIZES = [4000, 32000, 256000, 1000000]
SCALE_DT = 0.05  # model B's step
# A step at a million particles takes most of a second: blocks of 1 s (2 steps) read GW's
# rate there anywhere from 1.2 to 2.5 steps/s.
SCALE_SECONDS = 3.0
GPU_SCALE_SIZES = [32000, 256000, 1000000]
GPU_SCALE_INTEGRATORS = ["GW", "S1", "Lowe", "Langevin"] + (["OpenMM-DPD"] if hasattr(openmm, "DPDIntegrator") else [])
SCALE_REFERENCES = ("GW", "Langevin")
SUMMARY = ("particle-steps/s from 4000 to a million particles, against GW and Langevin (5 integrators, "
           "1 thread, 3 rounds: roughly 10 minutes)")
DURATION = ("With its default sizes (4000 to a million particles, 5 integrators) a run takes roughly 10 minutes "
            "on 2 cores (an estimate; the run in docs/benchmarks.md, 7 integrators at 32000 and a million in 5 "
            "rounds, took 11); the time grows with the sizes, the integrators and --repeats.")


def add_parsers(modes):
    parser = add_mode(modes, "scale", SUMMARY, f"{__doc__.splitlines()[0]} {DURATION}", run)
    add_system_arguments(parser, f"{joined(SCALE_SIZES)} ({joined(GPU_SCALE_SIZES)} on a GPU platform)", [1],
                         SCALE_DT)
    add_integrators_argument(parser, f"{joined(SCALE_INTEGRATORS)} ({joined(GPU_SCALE_INTEGRATORS)} on a GPU "
                             "platform)", edpd=True)
    add_round_arguments(parser, SCALE_SECONDS, "interleaved rounds: steps/s the best, ratios their medians")
    add_platform_argument(parser)


def run(args):
    gpu = args.platform != "CPU"
    args.sizes = args.sizes or (GPU_SCALE_SIZES if gpu else SCALE_SIZES)
    names = args.integrators or (GPU_SCALE_INTEGRATORS if gpu else SCALE_INTEGRATORS)
    print_scale_table(measure_scale(names, args), args)


def measure_scale(names, args):
    """Rows (N, threads, measure_in_groups's results)."""
    rows = []
    for n in args.sizes:
        for threads in args.threads:
            print(f"measuring N={n} threads={threads} ...", file=sys.stderr, flush=True)
            rows.append((n, threads, measure_in_groups(n, names, threads, args)))
    return rows


def measure_in_groups(n, names, threads, args):
    """{label: (best steps/s, speed/GW, cost/Langevin)}: the references (GW, Langevin) timed
    alone, then each other integrator timed interleaved with them, so that every ratio comes
    from runs side by side (the median over the rounds of each round's ratio) and at most three
    Contexts share the memory (all of them at once slow one another down at a million
    particles: docs/benchmarks.md, "How scale times"). Each group runs in a fresh process
    (measure_group). The references run in every group: their rates and their ratio to each
    other come from all those rounds (a slow spell of the host can take a whole group)."""
    references = [name for name in names if name in SCALE_REFERENCES]
    others = [name for name in names if name not in SCALE_REFERENCES]
    groups = [references] + [references + [name] for name in others] if references else [[name] for name in others]
    results, reference_rounds = {}, {name: [] for name in references}
    for group in groups:
        print(f"  {' '.join(group)} ...", file=sys.stderr, flush=True)
        rates = measure_group(n, group, threads, args)
        if all(isinstance(rates[name], list) for name in references):
            for name in references:
                reference_rounds[name] += rates[name]
        for label, own in rates.items():
            results.setdefault(label, scale_figures(own, rates))
    for name, own in reference_rounds.items():
        if own:
            results[name] = scale_figures(own, reference_rounds)
    return {name: results[name] for name in names}


def scale_figures(own, rounds):
    """(best steps/s, speed/GW, cost/Langevin) of an integrator's rounds `own`, against the
    references' rounds side by side with them in `rounds`."""
    return best_round(own), median_ratio(own, rounds.get("GW")), median_ratio(rounds.get("Langevin"), own)


def measure_group(n, names, threads, args):
    """measure_repeats's rates of `names` on model B with n particles, in a fresh process: in
    one that has made and dropped Contexts, GW at a million read up to a third slower (its
    passes over whole per-particle arrays took 1.3-7 times the samples; docs/benchmarks.md, "How
    scale times")."""
    try:
        return in_fresh_process(group_rates, n, names, threads, args)
    except BrokenProcessPool as error:  # killed (memory?)
        return {name: f"failed: {error}" for name in names}


def group_rates(n, names, threads, args):
    return measure_repeats(soft_scene(num_particles=n), [(name, factory(name, args.edpd_alpha), threads) for name in names],
                           args)


def print_scale_table(rows, args):
    """Particle-steps/s (best round); speed against GW and cost against Langevin at the same N,
    from the rounds interleaved with it; cost per particle-step against the first N's."""
    print(f"scene soft (model B: rho=4, a=25, DPDSoftRepulsionForce), {args.platform} platform, dt={args.dt:g}, "
          f"gamma={FRICTION:g}, {args.repeats} rounds of {args.seconds:g} s blocks, each integrator interleaved with "
          f"GW and Langevin; steps/s: best round; speed/GW = steps/s / GW's, cost/Langevin = time per step / "
          f"Langevin's: medians over the rounds of each round's ratio; cost/particle = time per particle-step (best "
          f"round) / the integrator's at N={rows[0][0]}")
    print(f"{'N':>8} {'threads':>7}  {'integrator':<10} {'steps/s':>9} {'Mparticle-steps/s':>17}  "
          f"{'speed/GW':>8} {'cost/Langevin':>13} {'cost/particle':>13}")
    first = {}
    for n, threads, results in rows:
        for label, (rate, speed, cost) in results.items():
            if isinstance(rate, str):
                print(f"{n:>8} {threads:>7}  {label:<10} {rate}")
                continue
            first.setdefault((threads, label), n * rate)
            print(f"{n:>8} {threads:>7}  {label:<10} {rate:>9.2f} {n * rate / 1e6:>17.3f}  "
                  f"{two_places(speed):>8} {two_places(cost):>13} {ratio(first[threads, label], n * rate):>13}")
