"""Steps per second of our integrators against OpenMM's LangevinMiddleIntegrator.

Scene `soft` on the CPU platform; every integrator runs the same System. Measurements of
one (size, threads) are interleaved and the best of --repeats kept, because a shared
machine's noise only ever slows a run down.

    /usr/bin/python3 -m openmmdpd.bench [--sizes 4000 32000] [--threads 1 2] [--dt 0.04]

--staggered instead measures StaggeredDPDIntegrator on scene fene-chains (4 chains of M
beads in 4000 particles): for each M and K, the wall time per unit of simulated time at the
same inner step dt (speed-up against K = 1) and the chain and total <kT> error:

    /usr/bin/python3 -m openmmdpd.bench --staggered [--chain-lengths 20 100] [--sub-steps 1 2 5 10 20]

--sentinel instead measures what the instability sentinel costs: GW (lambda 0.5) with the
threshold off and at INSTABILITY_THRESHOLD, alternated --repeats times, medians side by side;
--shear RATE likewise what Lees-Edwards shear costs each of --integrators:

    /usr/bin/python3 -m openmmdpd.bench --sentinel --sizes 32000 --threads 1 --repeats 9
    /usr/bin/python3 -m openmmdpd.bench --shear 0.1 --integrators GW S1 --sizes 32000 --threads 1 --repeats 9

--scale instead measures particle-steps/s from 4000 to a million particles on model B (dt 0.05,
one thread unless --threads says otherwise), each integrator against GW and Langevin at the
same N (timed interleaved with the two, three Contexts at a time, each group in a fresh
process) and against itself at the first N; --memory the bytes per particle a Context of each
integrator adds to the resident memory (each in a fresh process):

    /usr/bin/python3 -m openmmdpd.bench --scale --memory [--sizes 4000 32000 256000 1000000]

--thread-scaling instead measures each integrator's speed-up with threads on model B (default:
GW, S1 and Langevin at N = 256000, 1 and 2 threads), its Contexts at each thread count timed
interleaved in a process of their own; then, as the ceiling for that speed-up, as many
one-thread copies in processes of their own, all at once against one alone:

    /usr/bin/python3 -m openmmdpd.bench --thread-scaling [--sizes 256000] [--threads 1 2]

--platform OpenCL or CUDA measures on that platform instead of the CPU's (its default
precision; --threads does not apply); with --scale the sizes are then 32000, 256000 and a
million, the integrators GW, S1, Lowe, Langevin and, on OpenMM >= 8.3, OpenMM's DPDIntegrator:

    /usr/bin/python3 -m openmmdpd.bench --scale --platform OpenCL
"""
import ctypes
from concurrent.futures import ProcessPoolExecutor
from concurrent.futures.process import BrokenProcessPool
import gc
import multiprocessing
import os
import queue
import statistics
import sys
import threading
import time

import openmm

from . import EDPDIntegrator
from .catalog import CUTOFF, FRICTION, INSTABILITY_THRESHOLD, integrators
from .scenes import soft_scene
from .units import KT_TEMPERATURE
from . import options, staggered

DEFAULT_INTEGRATORS = ["Langevin", "GW", "DPD-VV", "SC-VV", "S1", "S2", "Lowe", "PairOU", "OC"]
SCALE_INTEGRATORS = ["GW", "DPD-VV", "S1", "Lowe", "Langevin"]
MEMORY_INTEGRATORS = SCALE_INTEGRATORS + ["EDPD"]
SCALE_SIZES = [4000, 32000, 256000, 1000000]
THREAD_SCALING_INTEGRATORS = ["GW", "S1", "Langevin"]
THREAD_SCALING_SIZES = [256000]
COPY_TIMEOUT = 600.0  # s: the longest one copy may wait for the others (their setup at a million particles included)
SCALE_DT = 0.05  # model B's step
# A step at a million particles takes most of a second: blocks of 1 s (2 steps) read GW's
# rate there anywhere from 1.2 to 2.5 steps/s.
SCALE_SECONDS = 3.0
GPU_SCALE_SIZES = [32000, 256000, 1000000]
GPU_SCALE_INTEGRATORS = ["GW", "S1", "Lowe", "Langevin"] + (["OpenMM-DPD"] if hasattr(openmm, "DPDIntegrator") else [])
# --memory: steps between readings of the resident memory, and the size of the throw-away
# Context made first in each measuring process.
MEMORY_CHUNK_STEPS = 5
MEMORY_WARM_N = 125


def no_wait():
    pass


def steps_per_second(integrator, steps, wait=no_wait):
    """wait(): returns when the steps are done (a GPU platform queues them and returns at once)."""
    start = time.perf_counter()
    integrator.step(steps)
    wait()
    return steps / (time.perf_counter() - start)


def warm_up(integrator, args, wait=no_wait):
    """Untimed steps: the first pays for the Context's setup; then up to args.warmup - 1 more,
    stopping after args.seconds (a step at a million particles takes most of a second).
    Returns the rate of those after the first, to size the timed runs."""
    integrator.step(1)
    wait()
    steps, start = 0, time.perf_counter()
    while steps == 0 or (steps < args.warmup - 1 and time.perf_counter() - start < args.seconds):
        integrator.step(1)
        wait()
        steps += 1
    return steps / (time.perf_counter() - start)


def timed_steps(rate, args):
    """Steps per timed run: --steps, or about --seconds worth (at least 2)."""
    return args.steps or max(2, round(rate * args.seconds))


def waiter(context, args):
    """What waits for a Context's queued steps: on a GPU platform, a State (it needs them done)."""
    return no_wait if args.platform == "CPU" else lambda: context.getState(getVelocities=True)


def make_context(system, integrator, threads, args):
    """A Context on --platform: the CPU's with `threads` threads, a GPU's with its defaults."""
    platform = openmm.Platform.getPlatformByName(args.platform)
    properties = {"Threads": str(threads)} if args.platform == "CPU" else {}
    return openmm.Context(system, integrator, platform, properties)


def started_context(scene, make, threads, args):
    """make_context for make(args.dt) on the scene, at its positions and velocities drawn at kT (seed 1)."""
    context = make_context(scene.system, make(args.dt), threads, args)
    context.setPositions(scene.positions)
    context.setVelocitiesToTemperature(KT_TEMPERATURE, 1)
    return context


def measure(scene, factories, threads, args):
    """{label: best steps/s, or the error that stopped it} for one system and thread count."""
    return {label: best_round(rates)
            for label, rates in measure_repeats(scene, [(label, make, threads) for label, make in factories], args).items()}


def best_round(rates):
    """The best of measure_repeats's rounds, or the error that stopped them."""
    return max(rates) if isinstance(rates, list) else rates


def measure_repeats(scene, factories, args):
    """{label: steps/s of each of --repeats interleaved rounds, or the error that stopped it};
    factories: (label, make(dt) -> integrator, threads)."""
    runs, results = {}, {}
    for label, make, threads in factories:
        try:
            context = started_context(scene, make, threads, args)
            rate = warm_up(context.getIntegrator(), args, waiter(context, args))
        except openmm.OpenMMException as error:
            results[label] = f"failed: {error}"
            continue
        runs[label] = (context, timed_steps(rate, args))
        results[label] = []
    for _ in range(args.repeats):
        for label, (context, steps) in list(runs.items()):
            try:
                results[label].append(steps_per_second(context.getIntegrator(), steps, waiter(context, args)))
            except openmm.OpenMMException as error:
                results[label] = f"failed: {error}"
                del runs[label]
    return results


def calls_per_second(context, calls):
    start = time.perf_counter()
    for _ in range(calls):
        context.getState(getForces=True)
    return calls / (time.perf_counter() - start)


def measure_soft_force(n, threads, args):
    """The soft repulsion alone and a GW DPD-VV step, with this plugin's DPDSoftRepulsionForce
    and with the same interaction as a CustomNonbondedForce: {label: best rate}."""
    platform = openmm.Platform.getPlatformByName("CPU")
    runs, contexts = {}, []  # the contexts must outlive the measurements
    for kind, native in (("native", True), ("CustomNonbonded", False)):
        scene = soft_scene(num_particles=n, native_force=native)
        force_context = openmm.Context(scene.system, openmm.VerletIntegrator(args.dt), platform, {"Threads": str(threads)})
        force_context.setPositions(scene.positions)
        contexts.append(force_context)
        rate = calls_per_second(force_context, 3)
        runs[f"force only, {kind}"] = (lambda c=force_context, k=max(3, round(rate * args.seconds)): calls_per_second(c, k))
        integrator = integrators()["GW"](args.dt)
        step_context = openmm.Context(scene.system, integrator, platform, {"Threads": str(threads)})
        step_context.setPositions(scene.positions)
        step_context.setVelocitiesToTemperature(KT_TEMPERATURE, 1)
        contexts.append(step_context)
        rate = warm_up(integrator, args)
        runs[f"GW step, {kind}"] = (lambda i=integrator, k=max(3, round(rate * args.seconds)): steps_per_second(i, k))
    results = {label: 0.0 for label in runs}
    for _ in range(args.repeats):
        for label, run in runs.items():
            results[label] = max(results[label], run())
    return results


def print_force_table(rows):
    print(f"{'N':>6} {'threads':>7}  {'what':<28} {'per s':>9}  {'native speed-up':>15}")
    for n, threads, results in rows:
        for label, rate in results.items():
            kind, _, which = label.partition(", ")
            speedup = f"{rate / results[kind + ', CustomNonbonded']:.2f}" if which == "native" else ""
            print(f"{n:>6} {threads:>7}  {label:<28} {rate:>9.1f}  {speedup:>15}")


def print_table(rows):
    print(f"{'N':>6} {'threads':>7}  {'integrator':<16} {'steps/s':>9}  "
          f"{'time/step vs Langevin':>21}  {'speed-up vs 1 thread':>20}")
    one_thread = {(n, label): rate for n, threads, results in rows if threads == 1
                  for label, rate in results.items()}
    for n, threads, results in rows:
        reference = results.get("Langevin")
        for label, rate in results.items():
            if isinstance(rate, str):
                print(f"{n:>6} {threads:>7}  {label:<16} {rate}")
                continue
            ratio = f"{reference / rate:.2f}" if isinstance(reference, float) else "-"
            base = one_thread.get((n, label))
            speedup = f"{rate / base:.2f}" if threads != 1 and isinstance(base, float) else ""
            print(f"{n:>6} {threads:>7}  {label:<16} {rate:>9.1f}  {ratio:>21}  {speedup:>20}")


def measure_sizes(factories, args):
    """Rows (N, threads, measure's results): one scene per N, shared by every integrator."""
    rows = []
    for n in args.sizes:
        scene = soft_scene(num_particles=n)
        for threads in args.threads:
            print(f"measuring N={n} threads={threads} ...", file=sys.stderr, flush=True)
            rows.append((n, threads, measure(scene, factories, threads, args)))
    return rows


def measure_scale(names, args):
    """Rows (N, threads, measure_in_groups's results) for --scale."""
    rows = []
    for n in args.sizes:
        for threads in args.threads:
            print(f"measuring N={n} threads={threads} ...", file=sys.stderr, flush=True)
            rows.append((n, threads, measure_in_groups(n, names, threads, args)))
    return rows


SCALE_REFERENCES = ("GW", "Langevin")


def median_ratio(numerators, denominators):
    """The median over rounds of numerator / denominator of the same round (a slow spell of
    the machine slows both), or '-' if either failed."""
    if not (isinstance(numerators, list) and isinstance(denominators, list)):
        return "-"
    return statistics.median(a / b for a, b in zip(numerators, denominators))


def measure_in_groups(n, names, threads, args):
    """{label: (best steps/s, speed/GW, cost/Langevin)}: the references (GW, Langevin) timed
    alone, then each other integrator timed interleaved with them, so that every ratio comes
    from runs side by side (the median over the rounds of each round's ratio) and at most three
    Contexts share the memory (all of them at once slow one another down at a million
    particles: see the README). Each group runs in a fresh process (measure_group). The
    references run in every group: their rates and their ratio to each other come from all
    those rounds (a slow spell of the host can take a whole group)."""
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
            best = best_round(own)
            results.setdefault(label, (best, median_ratio(own, rates.get("GW")), median_ratio(rates.get("Langevin"), own)))
    for name, own in reference_rounds.items():
        if own:
            results[name] = (max(own), median_ratio(own, reference_rounds.get("GW")),
                             median_ratio(reference_rounds.get("Langevin"), own))
    return {name: results[name] for name in names}


def measure_group(n, names, threads, args):
    """measure_repeats's rates of `names` on model B with n particles, in a fresh process: in
    one that has made and dropped Contexts, GW at a million read up to a third slower (its
    passes over whole per-particle arrays took 1.3-7 times the samples; see the README)."""
    try:
        return in_fresh_process(group_rates, n, names, threads, args)
    except BrokenProcessPool as error:  # killed (memory?)
        return {name: f"failed: {error}" for name in names}


def group_rates(n, names, threads, args):
    return measure_repeats(soft_scene(num_particles=n), [(name, factory(name, args.edpd_alpha), threads) for name in names],
                           args)


def measure_thread_scaling(names, args):
    """Rows (N, integrator, {threads: best steps/s}, {threads: speed-up}) for --thread-scaling:
    each integrator's Contexts at every thread count interleaved, round by round, in a process
    of its own; a speed-up is the median over the rounds of the round's rate / the first thread
    count's (a busy spell of the shared host slows a whole round, not one Context)."""
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


def measure_copies(names, args):
    """Rows (N, integrator, copies, speed-up) for --thread-scaling: as many one-thread copies as
    the most threads, in processes of their own, their steps/s summed while all run, against
    one copy alone (the median over the rounds, alternated): what the host gives work that
    shares no memory and never waits, the ceiling for the threads' speed-up."""
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
    failed = [result for result in rounds.values() if isinstance(result, str)]
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
    except (openmm.OpenMMException, threading.BrokenBarrierError) as error:
        barrier.abort()
        results.put((index, f"failed: {error}"))


def steps_for_seconds(integrator, seconds):
    """Steps/s over steps taken one at a time until `seconds` have passed: copies that start
    together are then timed over the same spell, however their speeds differ."""
    steps, start = 0, time.perf_counter()
    while steps == 0 or time.perf_counter() - start < seconds:
        integrator.step(1)
        steps += 1
    return steps / (time.perf_counter() - start)


def thread_rates(n, name, args):
    """{threads: steps/s of each round} of integrator `name` on model B with n particles."""
    make = factory(name, args.edpd_alpha)
    return measure_repeats(soft_scene(num_particles=n), [(threads, make, threads) for threads in args.threads], args)


def print_thread_scaling_table(rows, args):
    print(f"scene soft (model B: rho=4, a=25, DPDSoftRepulsionForce), CPU platform, dt={args.dt:g}, gamma=4.5; "
          f"each integrator at {', '.join(map(str, args.threads))} threads interleaved, {args.repeats} rounds of "
          f"{args.seconds:g} s blocks; steps/s: best round; speed-up: median over the rounds of the round's "
          f"rate / its rate at {args.threads[0]} thread(s)")
    print(f"{'N':>8}  {'integrator':<10} {'threads':>7} {'steps/s':>9} {'speed-up':>8}")
    for n, name, best, speedup in rows:
        for threads in args.threads:
            rate = best[threads]
            if isinstance(rate, str):
                print(f"{n:>8}  {name:<10} {threads:>7} {rate}")
                continue
            print(f"{n:>8}  {name:<10} {threads:>7} {rate:>9.2f} {two_places(speedup[threads]):>8}")


def print_copies_table(rows, args):
    print(f"one-thread copies in processes of their own, alone and all at once, alternated, {args.repeats} rounds of "
          f"{args.seconds:g} s blocks; speed-up: median over the rounds of the copies' summed steps/s / one copy's "
          f"alone (what the host gives work that shares nothing: the threads' ceiling)")
    print(f"{'N':>8}  {'integrator':<10} {'copies':>7} {'speed-up':>8}")
    for n, name, copies, speedup in rows:
        print(f"{n:>8}  {name:<10} {copies:>7} {two_places(speedup) if not isinstance(speedup, str) else speedup:>8}")


def in_fresh_process(function, *arguments):
    """function(*arguments), run in a new Python process (spawned: nothing of this one's memory)."""
    with ProcessPoolExecutor(1, mp_context=multiprocessing.get_context("spawn")) as process:
        return process.submit(function, *arguments).result()


def ratio(a, b):
    return f"{a / b:.2f}" if isinstance(a, float) and isinstance(b, float) and b > 0 else "-"


def two_places(x):
    return f"{x:.2f}" if isinstance(x, float) else "-"


def print_scale_table(rows, args):
    """Particle-steps/s (best round); speed against GW and cost against Langevin at the same N,
    from the rounds interleaved with it; cost per particle-step against the first N's."""
    print(f"scene soft (model B: rho=4, a=25, DPDSoftRepulsionForce), {args.platform} platform, dt={args.dt:g}, "
          f"gamma=4.5, {args.repeats} rounds of {args.seconds:g} s blocks, each integrator interleaved with GW and "
          f"Langevin; steps/s: best round; speed/GW = steps/s / GW's, cost/Langevin = time per step / Langevin's: "
          f"medians over the rounds of each round's ratio; cost/particle = time per particle-step (best round) / "
          f"the integrator's at N={rows[0][0]}")
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


def factory(name, edpd_alpha):
    """The catalog's integrator `name`, or "EDPD" (not in the catalog: its alpha is ours)."""
    if name == "EDPD":
        return lambda dt: EDPDIntegrator(KT_TEMPERATURE, FRICTION, CUTOFF, edpd_alpha, dt)
    return integrators("soft")[name]


def context_memory(name, n, threads, dt, edpd_alpha, max_steps):
    """In a fresh process (see measure_memory): the growth of the resident memory from before
    a Context of `name` on model B with n particles is made until it stops growing (a chunk of
    steps adds < 1 % to it and to EDPD's pair variables, or max_steps), as (bytes per
    particle, steps run, EDPD's pair variables per particle or None)."""
    platform = openmm.Platform.getPlatformByName("CPU")
    make = factory(name, edpd_alpha)

    def start(scene):
        context = openmm.Context(scene.system, make(dt), platform, {"Threads": str(threads)})
        context.setPositions(scene.positions)
        context.setVelocitiesToTemperature(KT_TEMPERATURE, 1)
        context.getIntegrator().step(1)
        return context

    # What every Context loads once (code pages, the platform's one-time data) is not per
    # particle: a small Context made and dropped first takes it out of the reading.
    start(soft_scene(num_particles=MEMORY_WARM_N))
    scene = soft_scene(num_particles=n)
    release_free_memory()
    before = resident_bytes()
    context = start(scene)  # held: the integrator lives as long as its Context
    integrator, steps = context.getIntegrator(), 1
    pairs = integrator.getNumPairVariables if name == "EDPD" else lambda: 0
    while steps < max_steps:
        last = resident_bytes(), pairs()
        integrator.step(MEMORY_CHUNK_STEPS)
        steps += MEMORY_CHUNK_STEPS
        now = resident_bytes(), pairs()
        if now[0] - last[0] < 0.01 * (now[0] - before) and now[1] - last[1] <= 0.01 * now[1]:
            break
    return (resident_bytes() - before) / n, steps, pairs() / n if name == "EDPD" else None


def measure_memory(args):
    """Rows (N, name, context_memory's result or the error), each in a fresh process: in one
    that has already made and dropped Contexts, malloc hands freed memory to the next one
    and the growth reads low."""
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


def measure_staggered(args):
    """Rows (M, K, Dt, seconds per unit time, speed-up, run) for --staggered.

    Timing: best of --repeats interleaved runs of --timed-time simulated time per K (a
    shared machine's noise only ever slows a run down). <kT>: one run of --sample-time per K,
    every K starting from the same equilibrated state."""
    threads = args.threads[0]
    rows = []
    for m in args.chain_lengths:
        print(f"equilibrating fene-chains M={m} ...", file=sys.stderr, flush=True)
        scene, state = staggered.equilibrated_fene_chains(chain_length=m, threads=threads)
        contexts = {}
        for k in args.sub_steps:
            integrator = staggered.staggered_integrator(k, args.inner_dt, args.base)
            context = openmm.Context(scene.system, integrator, openmm.Platform.getPlatformByName("CPU"),
                                     {"Threads": str(threads)})
            context.setState(state)
            integrator.step(2)
            contexts[k] = (context, integrator, max(1, round(args.timed_time / (k * args.inner_dt))))
        # The non-staggered reference: DPDVVIntegrator GW (lambda 0.65) at dt, the same System.
        gw = integrators()["GW0.65"](args.inner_dt)
        context = openmm.Context(scene.system, gw, openmm.Platform.getPlatformByName("CPU"), {"Threads": str(threads)})
        context.setState(state)
        gw.step(2)
        contexts["GW"] = (context, gw, max(1, round(args.timed_time / args.inner_dt)))
        best = {k: float("inf") for k in contexts}
        for _ in range(args.repeats):
            for k, (context, integrator, steps) in contexts.items():
                start = time.perf_counter()
                integrator.step(steps)
                outer = args.inner_dt * (1 if k == "GW" else k)
                best[k] = min(best[k], (time.perf_counter() - start) / (steps * outer))
        del contexts
        rows.append((m, "GW", args.inner_dt, best["GW"], best[args.sub_steps[0]] / best["GW"], None))
        for k in args.sub_steps:
            print(f"sampling M={m} K={k} ...", file=sys.stderr, flush=True)
            run = staggered.run_fene_chains(scene, state, k, args.inner_dt, args.sample_time, base=args.base,
                                            threads=threads)
            rows.append((m, k, k * args.inner_dt, best[k], best[args.sub_steps[0]] / best[k], run, best["GW"] / best[k]))
    return rows


def measure_paired(n, threads, args, name, change):
    """Integrator `name` as is and with change(integrator) applied, alternated: (median
    steps/s as is, median changed, median of the per-round cost changed/as-is - 1).
    Medians, since the two may differ by less than the noise."""
    platform = openmm.Platform.getPlatformByName("CPU")
    scene = soft_scene(num_particles=n)
    runs = []
    for changed in (False, True):
        integrator = integrators()[name](args.dt)
        if changed:
            change(integrator)
        context = openmm.Context(scene.system, integrator, platform, {"Threads": str(threads)})
        context.setPositions(scene.positions)
        context.setVelocitiesToTemperature(KT_TEMPERATURE, 1)
        runs.append((context, integrator, timed_steps(warm_up(integrator, args), args)))
    plain, changed = [], []
    for _ in range(args.repeats):
        for rates, (_, integrator, steps) in zip((plain, changed), runs):
            rates.append(steps_per_second(integrator, steps))
    cost = statistics.median(a / b - 1 for a, b in zip(plain, changed))
    return statistics.median(plain), statistics.median(changed), cost


def print_paired(args, title, names, columns, change):
    print(title)
    print(f"{'integrator':>10} {'N':>6} {'threads':>7}  {columns[0]:>14} {columns[1]:>14}  {'cost':>8}")
    for name in names:
        for n in args.sizes:
            for threads in args.threads:
                plain, changed, cost = measure_paired(n, threads, args, name, change)
                print(f"{name:>10} {n:>6} {threads:>7}  {plain:>14.2f} {changed:>14.2f}  {100 * cost:>+7.2f}%")


def print_staggered_table(rows, args):
    print(f"scene fene-chains (4 chains x M beads, 4000 particles), StaggeredDPDIntegrator base {args.base} "
          f"(Symeonidis and Karniadakis' recommended parameters), CPU platform, {args.threads[0]} thread(s), inner dt={args.inner_dt:g}; "
          f"speed-up at equal simulated time against K={args.sub_steps[0]} (best of {args.repeats}); "
          f"<kT> - 1 over {args.sample_time:g} time units (+- standard error)")
    print("(row GW: DPDVVIntegrator Groot-Warren, lambda 0.65, at dt on the same System; 'vs GW' is the "
          "speed-up against it)")
    print(f"{'M':>4} {'K':>3} {'Dt':>6}  {'s per unit time':>15} {'speed-up':>8} {'vs GW':>6}  "
          f"{'chain <kT> - 1':>20}  {'total <kT> - 1':>20}")
    for m, k, outer, seconds, speedup, run, *versus in rows:
        if run is None:
            print(f"{m:>4} {k:>3} {outer:>6.3f}  {seconds:>15.2f} {speedup:>8.2f} {1:>6.2f}")
            continue
        chain, chain_error = run["chain_kT"]
        total, total_error = run["total_kT"]
        print(f"{m:>4} {k:>3} {outer:>6.3f}  {seconds:>15.2f} {speedup:>8.2f} {versus[0]:>6.2f}  "
              f"{chain - 1:>+10.4f} +- {chain_error:.4f}  {total - 1:>+10.4f} +- {total_error:.4f}")


# How long a run with the defaults takes, for --help (docs/benchmarks.md has the measured ones).
DURATION = ("With the defaults (scene soft, 9 integrators at N 4000 and 32000 on 1 and 2 threads, best of 3 "
            "rounds of about 1 s each) a run takes about 3 minutes on 2 cores: about 1 s per integrator, size, "
            "thread count and round (--seconds), plus building each System. --scale with its default sizes "
            "(4000 to a million particles, 5 integrators) takes roughly 10 minutes (an estimate; the run in docs/benchmarks.md, "
            "7 integrators at 32000 and a million in 5 rounds, took 11), --staggered about a minute, "
            "--thread-scaling and --memory a few minutes; the time grows with the sizes, the integrators and "
            "--repeats.")


def _parser():
    parser = options.parser("bench", __doc__.splitlines()[0], DURATION)
    parser.add_argument("--sizes", type=int, nargs="+",
                        help=f"default 4000 32000 ({' '.join(map(str, SCALE_SIZES))} with --scale, --memory)")
    parser.add_argument("--threads", type=int, nargs="+", help="default 1 2 (1 with --scale, --memory)")
    parser.add_argument("--dt", type=float,
                        help=f"time step (ps = reduced units), default 0.04 ({SCALE_DT:g} with --scale, --memory)")
    parser.add_argument("--integrators", nargs="+",
                        help=f"from: {', '.join(integrators('soft'))} (and EDPD with --scale, --memory); default "
                        f"{' '.join(DEFAULT_INTEGRATORS)} ({' '.join(SCALE_INTEGRATORS)} with --scale, "
                        f"{' '.join(MEMORY_INTEGRATORS)} with --memory)")
    parser.add_argument("--warmup", type=int, default=10, help="untimed steps per integrator")
    parser.add_argument("--steps", type=int, default=None,
                        help="timed steps per measurement (default: about --seconds worth)")
    parser.add_argument("--seconds", type=float,
                        help=f"target length of one measurement when --steps is not given, default 1 "
                        f"({SCALE_SECONDS:g} with --scale)")
    parser.add_argument("--repeats", type=int, default=3,
                        help="interleaved measurements; best kept (with --scale: rounds, ratios their medians)")
    parser.add_argument("--platform", default="CPU", choices=["CPU", "OpenCL", "CUDA"],
                        help="the platform measured (--scale and the default table)")
    parser.add_argument("--scale", action="store_true",
                        help="particle-steps/s and ratios from 4000 to a million particles instead")
    parser.add_argument("--thread-scaling", action="store_true",
                        help="each integrator's speed-up with --threads, paired round by round, instead")
    parser.add_argument("--memory", action="store_true",
                        help="bytes per particle of each integrator's Context instead (with --scale: as well)")
    parser.add_argument("--edpd-alpha", type=float, default=20.0,
                        help="EDPD's alpha (1/ps); its pair memory grows as alpha falls")
    parser.add_argument("--memory-steps", type=int, default=100,
                        help="--memory: most steps before the reading, if the memory still grows")
    parser.add_argument("--soft-force", action="store_true",
                        help="also compare DPDSoftRepulsionForce with the same CustomNonbondedForce")
    parser.add_argument("--sentinel", action="store_true",
                        help="measure GW with the instability sentinel off and on instead")
    parser.add_argument("--shear", type=float, default=0.0, metavar="RATE",
                        help="measure --integrators unsheared and sheared at RATE (1/ps) instead")
    parser.add_argument("--staggered", action="store_true",
                        help="measure StaggeredDPDIntegrator on fene-chains instead (see the module help)")
    parser.add_argument("--chain-lengths", type=int, nargs="+", default=[20, 100], help="--staggered: M")
    parser.add_argument("--sub-steps", type=int, nargs="+", default=[1, 2, 5, 10, 20], help="--staggered: K")
    parser.add_argument("--inner-dt", type=float, default=0.001, help="--staggered: the polymer step dt")
    parser.add_argument("--base", choices=["vv", "lowe"], default="vv", help="--staggered: base scheme")
    parser.add_argument("--timed-time", type=float, default=0.3,
                        help="--staggered: simulated time of one timed run")
    parser.add_argument("--sample-time", type=float, default=4.0,
                        help="--staggered: simulated time over which <kT> is sampled")
    return parser


def main(argv=None):
    parser = _parser()
    args = parser.parse_args(argv)
    if args.thread_scaling:
        if args.platform != "CPU":
            parser.error("--thread-scaling measures the CPU platform's threads: leave out --platform")
        args.sizes = args.sizes or THREAD_SCALING_SIZES
        args.threads = args.threads or [1, 2]
        args.dt = args.dt or SCALE_DT
        args.seconds = args.seconds or SCALE_SECONDS
        names = args.integrators or THREAD_SCALING_INTEGRATORS
        print_thread_scaling_table(measure_thread_scaling(names, args), args)
        if max(args.threads) > 1:
            print_copies_table(measure_copies(names, args), args)
        return
    at_scale = args.scale or args.memory
    gpu = args.platform != "CPU"
    args.sizes = args.sizes or ((GPU_SCALE_SIZES if gpu else SCALE_SIZES) if at_scale else [4000, 32000])
    args.threads = args.threads or ([1] if at_scale or gpu else [1, 2])
    args.dt = args.dt or (SCALE_DT if at_scale else 0.04)
    args.seconds = args.seconds or (SCALE_SECONDS if args.scale else 1.0)

    if at_scale:
        if args.scale:
            chosen = args.integrators or (GPU_SCALE_INTEGRATORS if gpu else SCALE_INTEGRATORS)
            print_scale_table(measure_scale(chosen, args), args)
        if args.memory:
            args.integrators = args.integrators or MEMORY_INTEGRATORS
            print_memory_table(measure_memory(args), args)
        return
    args.integrators = args.integrators or DEFAULT_INTEGRATORS

    if args.staggered:
        print_staggered_table(measure_staggered(args), args)
        return

    if args.sentinel:
        print_paired(args, f"scene soft, CPU platform, dt={args.dt:g}; instability threshold 0 (off) and "
                     f"{INSTABILITY_THRESHOLD:g} kT alternated, medians of {args.repeats}", ["GW"],
                     ("steps/s off", "steps/s on"), lambda i: i.setInstabilityThreshold(INSTABILITY_THRESHOLD))
        return
    if args.shear:
        print_paired(args, f"scene soft, CPU platform, dt={args.dt:g}; no shear and Lees-Edwards shear at rate "
                     f"{args.shear:g}/ps alternated, medians of {args.repeats}", args.integrators,
                     ("steps/s", "steps/s sheared"), lambda i: i.setShearRate(args.shear))
        return

    catalog = integrators("soft")  # with den Otter-Clarke ("OC") at model B's averages from Nikunen et al. 2003
    rows = measure_sizes([(name, catalog[name]) for name in args.integrators], args)
    print(f"scene soft (rho=4, a=25, DPDSoftRepulsionForce), {args.platform} platform, dt={args.dt:g}, "
          f"gamma=4.5, best of {args.repeats}")
    print_table(rows)
    if args.soft_force:
        force_rows = []
        for n in args.sizes:
            for threads in args.threads:
                print(f"measuring the soft force, N={n} threads={threads} ...", file=sys.stderr, flush=True)
                force_rows.append((n, threads, measure_soft_force(n, threads, args)))
        print("\nsoft repulsion: DPDSoftRepulsionForce against the same CustomNonbondedForce "
              "(force only: repeated force evaluations of one configuration)")
        print_force_table(force_rows)


if __name__ == "__main__":
    main()
