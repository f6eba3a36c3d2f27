"""StaggeredDPDIntegrator on scene fene-chains: speed-up and <kT> error against K.

4 chains of M beads in 4000 particles: for each M and K, the wall time per unit of simulated
time at the same inner step dt (speed-up against K = 1 and against GW at dt) and the chain
and total <kT> error.

    python3 -m openmmdpd.bench staggered [--chain-lengths 20 100] [--sub-steps 1 2 5 10 20]
"""
import sys
import time

import openmm

from . import staggered
from .bench_timing import add_list_argument, add_mode
from .catalog import integrators

SUMMARY = ("StaggeredDPDIntegrator's speed-up and <kT> error against K on fene-chains (M 20 100, "
           "K 1 2 5 10 20: about a minute)")
DURATION = ("With the defaults a run takes about a minute on 2 cores; the time grows with the chain lengths, "
            "the sub-steps, --repeats, --timed-time and --sample-time.")


def add_parsers(modes):
    parser = add_mode(modes, "staggered", SUMMARY, f"{__doc__.splitlines()[0]} {DURATION}", run)
    add_list_argument(parser, "--threads", [1], "threads of the CPU platform (the first is used)", int)
    parser.add_argument("--repeats", type=int, default=3, help="interleaved timed runs; best kept")
    add_list_argument(parser, "--chain-lengths", [20, 100], "M, beads per chain", int)
    add_list_argument(parser, "--sub-steps", [1, 2, 5, 10, 20], "K, sub-steps per outer step", int)
    parser.add_argument("--inner-dt", type=float, default=0.001, help="the polymer step dt")
    parser.add_argument("--base", choices=["vv", "lowe"], default="vv", help="base scheme")
    parser.add_argument("--timed-time", type=float, default=0.3, help="simulated time of one timed run")
    parser.add_argument("--sample-time", type=float, default=4.0, help="simulated time over which <kT> is sampled")


def run(args):
    print_staggered_table(measure_staggered(args), args)


def measure_staggered(args):
    """Rows (M, K, Dt, seconds per unit time, speed-up, run_fene_chains's result, speed-up against
    GW); GW's own row has None for the result and no last entry.

    Timing: best of --repeats interleaved runs of --timed-time simulated time per K (a
    shared machine's noise only ever slows a run down). <kT>: one run of --sample-time per K,
    every K starting from the same equilibrated state."""
    threads = args.threads[0]
    rows = []
    for m in args.chain_lengths:
        print(f"equilibrating fene-chains M={m} ...", file=sys.stderr, flush=True)
        scene, state = staggered.equilibrated_fene_chains(chain_length=m, threads=threads)
        best = best_seconds_per_unit_time(timed_contexts(scene, state, threads, args), args)
        rows.append((m, "GW", args.inner_dt, best["GW"], best[args.sub_steps[0]] / best["GW"], None))
        for k in args.sub_steps:
            print(f"sampling M={m} K={k} ...", file=sys.stderr, flush=True)
            sampled = staggered.run_fene_chains(scene, state, k, args.inner_dt, args.sample_time, base=args.base,
                                                threads=threads)
            rows.append((m, k, k * args.inner_dt, best[k], best[args.sub_steps[0]] / best[k], sampled,
                         best["GW"] / best[k]))
    return rows


def timed_contexts(scene, state, threads, args):
    """{K or "GW": (Context, integrator, steps per timed run)}, each from `state` and two steps on."""
    contexts = {}
    for k in list(args.sub_steps) + ["GW"]:
        integrator = timed_integrator(k, args)
        context = openmm.Context(scene.system, integrator, openmm.Platform.getPlatformByName("CPU"),
                                 {"Threads": str(threads)})
        context.setState(state)
        integrator.step(2)
        contexts[k] = (context, integrator, max(1, round(args.timed_time / outer_dt(k, args))))
    return contexts


def timed_integrator(k, args):
    """StaggeredDPDIntegrator with K = k; for "GW", the non-staggered reference: DPDVVIntegrator
    GW (lambda 0.65) at dt, on the same System."""
    if k == "GW":
        return integrators()["GW0.65"](args.inner_dt)
    return staggered.staggered_integrator(k, args.inner_dt, args.base)


def outer_dt(k, args):
    return args.inner_dt * (1 if k == "GW" else k)


def best_seconds_per_unit_time(contexts, args):
    """{K or "GW": the least wall time per unit of simulated time over --repeats interleaved runs}."""
    best = {k: float("inf") for k in contexts}
    for _ in range(args.repeats):
        for k, (context, integrator, steps) in contexts.items():
            start = time.perf_counter()
            integrator.step(steps)
            best[k] = min(best[k], (time.perf_counter() - start) / (steps * outer_dt(k, args)))
    return best


def print_staggered_table(rows, args):
    print(f"scene fene-chains (4 chains x M beads, 4000 particles), StaggeredDPDIntegrator base {args.base} "
          f"(Symeonidis and Karniadakis' recommended parameters), CPU platform, {args.threads[0]} thread(s), inner dt={args.inner_dt:g}; "
          f"speed-up at equal simulated time against K={args.sub_steps[0]} (best of {args.repeats}); "
          f"<kT> - 1 over {args.sample_time:g} time units (+- standard error)")
    print("(row GW: DPDVVIntegrator Groot-Warren, lambda 0.65, at dt on the same System; 'vs GW' is the "
          "speed-up against it)")
    print(f"{'M':>4} {'K':>3} {'Dt':>6}  {'s per unit time':>15} {'speed-up':>8} {'vs GW':>6}  "
          f"{'chain <kT> - 1':>20}  {'total <kT> - 1':>20}")
    for m, k, outer, seconds, speedup, sampled, *versus in rows:
        if sampled is None:
            print(f"{m:>4} {k:>3} {outer:>6.3f}  {seconds:>15.2f} {speedup:>8.2f} {1:>6.2f}")
            continue
        chain, chain_error = sampled["chain_kT"]
        total, total_error = sampled["total_kT"]
        print(f"{m:>4} {k:>3} {outer:>6.3f}  {seconds:>15.2f} {speedup:>8.2f} {versus[0]:>6.2f}  "
              f"{chain - 1:>+10.4f} +- {chain_error:.4f}  {total - 1:>+10.4f} +- {total_error:.4f}")
