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
"""
import argparse
import statistics
import sys
import time

import openmm

from .catalog import INSTABILITY_THRESHOLD, integrators
from .scenes import soft_scene
from .units import KT_TEMPERATURE
from . import staggered

DEFAULT_INTEGRATORS = ["Langevin", "GW", "DPD-VV", "SC-VV", "S1", "S2", "Lowe", "PairOU", "OC"]


def steps_per_second(integrator, steps):
    start = time.perf_counter()
    integrator.step(steps)
    return steps / (time.perf_counter() - start)


def measure(scene, factories, threads, args):
    """{label: best steps/s, or the error that stopped it} for one system and thread count."""
    platform = openmm.Platform.getPlatformByName("CPU")
    runs, results = {}, {}
    for label, make in factories:
        try:
            context = openmm.Context(scene.system, make(args.dt), platform, {"Threads": str(threads)})
            context.setPositions(scene.positions)
            context.setVelocitiesToTemperature(KT_TEMPERATURE, 1)
            rate = steps_per_second(context.getIntegrator(), args.warmup)
        except openmm.OpenMMException as error:
            results[label] = f"failed: {error}"
            continue
        runs[label] = (context, args.steps or max(5, round(rate * args.seconds)))
        results[label] = 0.0
    for _ in range(args.repeats):
        for label, (context, steps) in list(runs.items()):
            try:
                results[label] = max(results[label],
                                     steps_per_second(context.getIntegrator(), steps))
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
        rate = steps_per_second(integrator, args.warmup)
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
        rate = steps_per_second(integrator, args.warmup)
        runs.append((context, integrator, args.steps or max(5, round(rate * args.seconds))))
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
          f"(paper 002 recommended parameters), CPU platform, {args.threads[0]} thread(s), inner dt={args.inner_dt:g}; "
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


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[4000, 32000])
    parser.add_argument("--threads", type=int, nargs="+", default=[1, 2])
    parser.add_argument("--dt", type=float, default=0.04, help="time step (ps = reduced units)")
    parser.add_argument("--integrators", nargs="+", default=DEFAULT_INTEGRATORS,
                        help=f"from: {', '.join(integrators('soft'))}")
    parser.add_argument("--warmup", type=int, default=10, help="untimed steps per integrator")
    parser.add_argument("--steps", type=int, default=None,
                        help="timed steps per measurement (default: about --seconds worth)")
    parser.add_argument("--seconds", type=float, default=1.0,
                        help="target length of one measurement when --steps is not given")
    parser.add_argument("--repeats", type=int, default=3,
                        help="interleaved measurements; best kept")
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
    args = parser.parse_args(argv)

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

    catalog = integrators("soft")  # with den Otter-Clarke ("OC") at paper 000's model B averages
    factories = [(name, catalog[name]) for name in args.integrators]
    rows = []
    for n in args.sizes:
        scene = soft_scene(num_particles=n)
        for threads in args.threads:
            print(f"measuring N={n} threads={threads} ...", file=sys.stderr, flush=True)
            rows.append((n, threads, measure(scene, factories, threads, args)))
    print(f"scene soft (rho=4, a=25, DPDSoftRepulsionForce), CPU platform, dt={args.dt:g}, "
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
