"""Bytes per particle that a Context of each integrator adds to the resident memory.

Scene soft (model B) on the CPU platform, each Context in a fresh process (in one that has
already made and dropped Contexts, malloc hands freed memory to the next one and the growth
reads low).

    python3 -m openmmdpd.bench memory [--sizes 4000 32000 256000 1000000]
"""
from concurrent.futures.process import BrokenProcessPool
import ctypes
import gc
import os
import sys

import openmm

from .bench_scale import SCALE_DT, SCALE_INTEGRATORS, SCALE_SIZES
from .bench_timing import add_integrators_argument, add_mode, add_system_arguments, factory, in_fresh_process
from .scenes import soft_scene
from .units import KT_TEMPERATURE

MEMORY_INTEGRATORS = SCALE_INTEGRATORS + ["EDPD"]
# Steps between readings of the resident memory, and the size of the throw-away Context made
# first in each measuring process.
MEMORY_CHUNK_STEPS = 5
MEMORY_WARM_N = 125
SUMMARY = "bytes per particle of each integrator's Context (6 integrators, N 4000 to a million: a few minutes)"
DURATION = ("With the defaults a run takes a few minutes on 2 cores; the time grows with the sizes and the "
            "integrators.")


def add_parsers(modes):
    parser = add_mode(modes, "memory", SUMMARY, f"{__doc__.splitlines()[0]} {DURATION}", run)
    add_system_arguments(parser, SCALE_SIZES, [1], SCALE_DT,
                         threads_help="threads of the CPU platform (the first is used)")
    add_integrators_argument(parser, MEMORY_INTEGRATORS, edpd=True)
    parser.add_argument("--memory-steps", type=int, default=100,
                        help="most steps before the reading, if the memory still grows")


def run(args):
    print_memory_table(measure_memory(args), args)


def resident_bytes():
    """This process's resident memory (Linux)."""
    with open("/proc/self/statm") as statm:
        return int(statm.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")


def release_free_memory():
    """Hands the memory malloc holds free back to the system (glibc's malloc_trim), so that a
    Context reusing it is counted as it touches it again."""
    gc.collect()
    try:
        ctypes.CDLL(None).malloc_trim(0)
    except AttributeError:  # not glibc
        pass


def stepped_context(scene, make, threads, dt):
    """A CPU Context of make(dt) on the scene, one step on."""
    platform = openmm.Platform.getPlatformByName("CPU")
    context = openmm.Context(scene.system, make(dt), platform, {"Threads": str(threads)})
    context.setPositions(scene.positions)
    context.setVelocitiesToTemperature(KT_TEMPERATURE, 1)
    context.getIntegrator().step(1)
    return context


def context_memory(name, n, threads, dt, edpd_alpha, max_steps):
    """In a fresh process (see measure_memory): the growth of the resident memory from before
    a Context of `name` on model B with n particles is made until it stops growing (a chunk of
    steps adds < 1 % to it and to EDPD's pair variables, or max_steps), as (bytes per
    particle, steps run, EDPD's pair variables per particle or None)."""
    make = factory(name, edpd_alpha)
    # What every Context loads once (code pages, the platform's one-time data) is not per
    # particle: a small Context made and dropped first takes it out of the reading.
    stepped_context(soft_scene(num_particles=MEMORY_WARM_N), make, threads, dt)
    scene = soft_scene(num_particles=n)
    release_free_memory()
    before = resident_bytes()
    context = stepped_context(scene, make, threads, dt)  # held: the integrator lives as long as its Context
    integrator = context.getIntegrator()
    pairs = integrator.getNumPairVariables if name == "EDPD" else lambda: 0
    steps = step_until_settled(integrator, pairs, before, max_steps)
    return (resident_bytes() - before) / n, steps, pairs() / n if name == "EDPD" else None


def step_until_settled(integrator, pairs, before, max_steps):
    """Steps in chunks until one adds < 1 % to the memory grown since `before` and to pairs(),
    or max_steps; returns the steps run (the one already taken included)."""
    steps = 1
    while steps < max_steps:
        last = resident_bytes(), pairs()
        integrator.step(MEMORY_CHUNK_STEPS)
        steps += MEMORY_CHUNK_STEPS
        now = resident_bytes(), pairs()
        if now[0] - last[0] < 0.01 * (now[0] - before) and now[1] - last[1] <= 0.01 * now[1]:
            break
    return steps


def measure_memory(args):
    """Rows (N, name, context_memory's result or the error), each in a fresh process."""
    rows = []
    for n in args.sizes:
        for name in args.integrators:
            print(f"memory N={n} {name} ...", file=sys.stderr, flush=True)
            try:
                rows.append((n, name, in_fresh_process(context_memory, name, n, args.threads[0], args.dt,
                                                       args.edpd_alpha, args.memory_steps)))
            except (openmm.OpenMMException, BrokenProcessPool) as error:  # the latter: killed (memory?)
                rows.append((n, name, f"failed: {error}"))
    return rows


def print_memory_table(rows, args):
    print(f"resident memory a Context adds (OpenMM's Context and CPU platform data, the force's "
          f"and the integrator's buffers) per particle, scene soft, CPU platform, {args.threads[0]} "
          f"thread(s) (the first of --threads), dt={args.dt:g}, EDPD alpha={args.edpd_alpha:g}/ps; each in a "
          f"fresh process")
    print(f"{'N':>8}  {'integrator':<10} {'bytes/particle':>14} {'steps':>5} {'pair vars/particle':>18}")
    for n, name, result in rows:
        if isinstance(result, str):
            print(f"{n:>8}  {name:<10} {result}")
            continue
        per_particle, steps, pairs = result
        pairs = "-" if pairs is None else f"{pairs:.1f}"
        print(f"{n:>8}  {name:<10} {per_particle:>14.0f} {steps:>5} {pairs:>18}")
