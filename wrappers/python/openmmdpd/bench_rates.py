"""Steps per second of our integrators against OpenMM's LangevinMiddleIntegrator.

Scene `soft`; every integrator runs the same System. Measurements of one (size, threads) are
interleaved and the best of --repeats kept, because a shared machine's noise only ever slows a
run down. --soft-force then compares DPDSoftRepulsionForce with the same interaction as a
CustomNonbondedForce.

    python3 -m openmmdpd.bench rates [--sizes 4000 32000] [--threads 1 2] [--dt 0.04] [--soft-force]
"""
import sys
import time

import openmm

from .bench_timing import (add_integrators_argument, add_mode, add_platform_argument, add_round_arguments,
                           add_system_arguments, measure, steps_per_second, warm_up)
from .catalog import FRICTION, integrators
from .scenes import soft_scene
from .units import KT_TEMPERATURE

DEFAULT_INTEGRATORS = ["Langevin", "GW", "DPD-VV", "SC-VV", "S1", "S2", "Lowe", "PairOU", "OC"]
SUMMARY = ("steps/s of each integrator against Langevin at each size and thread count (9 integrators, "
           "N 4000 32000, 1 and 2 threads, best of 3: about 3 minutes)")
# How long a run with the defaults takes (docs/benchmarks.md has the measured ones).
DURATION = ("With the defaults (scene soft, 9 integrators at N 4000 and 32000 on 1 and 2 threads, best of 3 "
            "rounds of about 1 s each) a run takes about 3 minutes on 2 cores: about 1 s per integrator, size, "
            "thread count and round (--seconds), plus building each System. --soft-force adds 4 runs of about 1 s "
            "per size, thread count and round (an estimate); the time grows with the sizes, the integrators and "
            "--repeats.")


def add_parsers(modes):
    parser = add_mode(modes, "rates", SUMMARY, f"{__doc__.splitlines()[0]} {DURATION}", run)
    add_system_arguments(parser, [4000, 32000], "1 2 (1 on a GPU platform)", 0.04)
    add_integrators_argument(parser, DEFAULT_INTEGRATORS)
    add_round_arguments(parser, 1.0, "interleaved measurements; best kept")
    add_platform_argument(parser)
    parser.add_argument("--soft-force", action="store_true",
                        help="also compare DPDSoftRepulsionForce with the same CustomNonbondedForce (CPU platform)")


def run(args):
    args.threads = args.threads or ([1] if args.platform != "CPU" else [1, 2])
    catalog = integrators("soft")  # with den Otter-Clarke ("OC") at model B's averages from Nikunen et al. 2003
    rows = measure_sizes([(name, catalog[name]) for name in args.integrators], args)
    print(f"scene soft (rho=4, a=25, DPDSoftRepulsionForce), {args.platform} platform, dt={args.dt:g}, "
          f"gamma={FRICTION:g}, best of {args.repeats}")
    print_table(rows)
    if args.soft_force:
        print_soft_force(args)


def measure_sizes(factories, args):
    """Rows (N, threads, measure's results): one scene per N, shared by every integrator."""
    rows = []
    for n in args.sizes:
        scene = soft_scene(num_particles=n)
        for threads in args.threads:
            print(f"measuring N={n} threads={threads} ...", file=sys.stderr, flush=True)
            rows.append((n, threads, measure(scene, factories, threads, args)))
    return rows


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


def print_soft_force(args):
    rows = []
    for n in args.sizes:
        for threads in args.threads:
            print(f"measuring the soft force, N={n} threads={threads} ...", file=sys.stderr, flush=True)
            rows.append((n, threads, measure_soft_force(n, threads, args)))
    print("\nsoft repulsion: DPDSoftRepulsionForce against the same CustomNonbondedForce "
          "(force only: repeated force evaluations of one configuration)")
    print_force_table(rows)


def calls_per_second(context, calls):
    start = time.perf_counter()
    for _ in range(calls):
        context.getState(getForces=True)
    return calls / (time.perf_counter() - start)


def measure_soft_force(n, threads, args):
    """The soft repulsion alone and a GW DPD-VV step, with this plugin's DPDSoftRepulsionForce
    and with the same interaction as a CustomNonbondedForce: {label: best rate}."""
    runs, contexts = {}, []  # the contexts must outlive the measurements
    for kind, native in (("native", True), ("CustomNonbonded", False)):
        scene = soft_scene(num_particles=n, native_force=native)
        contexts += add_soft_force_runs(runs, kind, scene, threads, args)
    results = {label: 0.0 for label in runs}
    for _ in range(args.repeats):
        for label, run_once in runs.items():
            results[label] = max(results[label], run_once())
    return results


def add_soft_force_runs(runs, kind, scene, threads, args):
    """Adds to `runs` the force alone and a GW step on `scene`, each sized to about --seconds;
    returns their Contexts."""
    platform = openmm.Platform.getPlatformByName("CPU")
    force_context = openmm.Context(scene.system, openmm.VerletIntegrator(args.dt), platform, {"Threads": str(threads)})
    force_context.setPositions(scene.positions)
    rate = calls_per_second(force_context, 3)
    runs[f"force only, {kind}"] = (lambda c=force_context, k=max(3, round(rate * args.seconds)): calls_per_second(c, k))
    integrator = integrators()["GW"](args.dt)
    step_context = openmm.Context(scene.system, integrator, platform, {"Threads": str(threads)})
    step_context.setPositions(scene.positions)
    step_context.setVelocitiesToTemperature(KT_TEMPERATURE, 1)
    rate = warm_up(integrator, args)
    runs[f"GW step, {kind}"] = (lambda i=integrator, k=max(3, round(rate * args.seconds)): steps_per_second(i, k))
    return [force_context, step_context]


def print_force_table(rows):
    print(f"{'N':>6} {'threads':>7}  {'what':<28} {'per s':>9}  {'native speed-up':>15}")
    for n, threads, results in rows:
        for label, rate in results.items():
            kind, _, which = label.partition(", ")
            speedup = f"{rate / results[kind + ', CustomNonbonded']:.2f}" if which == "native" else ""
            print(f"{n:>6} {threads:>7}  {label:<28} {rate:>9.1f}  {speedup:>15}")
