"""What the bench's modes share: Contexts on a platform, warm-up, interleaved rounds of timed
steps, fresh processes, the ratios and table cells made from the rates, and the options."""
from concurrent.futures import ProcessPoolExecutor
import multiprocessing
import statistics
import time

import openmm

from . import EDPDIntegrator, options
from .catalog import CUTOFF, FRICTION, integrators
from .units import KT_TEMPERATURE


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


def factory(name, edpd_alpha):
    """The catalog's integrator `name`, or "EDPD" (not in the catalog: its alpha is ours)."""
    if name == "EDPD":
        return lambda dt: EDPDIntegrator(KT_TEMPERATURE, FRICTION, CUTOFF, edpd_alpha, dt)
    return integrators("soft")[name]


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


def in_fresh_process(function, *arguments):
    """function(*arguments), run in a new Python process (spawned: nothing of this one's memory)."""
    with ProcessPoolExecutor(1, mp_context=multiprocessing.get_context("spawn")) as process:
        return process.submit(function, *arguments).result()


def median_ratio(numerators, denominators):
    """The median over rounds of numerator / denominator of the same round (a slow spell of
    the machine slows both), or '-' if either failed."""
    if not (isinstance(numerators, list) and isinstance(denominators, list)):
        return "-"
    return statistics.median(a / b for a, b in zip(numerators, denominators))


def ratio(a, b):
    return f"{a / b:.2f}" if isinstance(a, float) and isinstance(b, float) and b > 0 else "-"


def two_places(x):
    return f"{x:.2f}" if isinstance(x, float) else "-"


def add_mode(modes, name, summary, description, run):
    """Subcommand `name` of the bench, which calls run(args): the bench's --help lists it with
    `summary`; its own --help gives `description`, then every option with its default."""
    parser = modes.add_parser(name, help=summary, description=description, formatter_class=options.HelpFormatter)
    parser.set_defaults(run=run)
    return parser


def add_list_argument(parser, flag, default, what, type=str, choices=None):
    """A list option (of `choices` only, where given). A default given as text is left None and
    said in the help: the mode picks it once it knows --platform."""
    # The metavar keeps a long list of choices out of the usage line; the help names them.
    named = dict(choices=choices, metavar=flag.lstrip("-").upper().replace("-", "_")) if choices else {}
    if isinstance(default, str):
        parser.add_argument(flag, type=type, nargs="+", help=f"{what}; default {default}", **named)
    else:
        parser.add_argument(flag, type=type, nargs="+", default=default, help=what, **named)


def add_system_arguments(parser, sizes, threads, dt, threads_help="threads of the CPU platform"):
    add_list_argument(parser, "--sizes", sizes, "numbers of particles", int)
    add_list_argument(parser, "--threads", threads, threads_help, int)
    parser.add_argument("--dt", type=float, default=dt, help="time step (ps = reduced units)")


def add_integrators_argument(parser, default, edpd=False, names=None):
    """--integrators, from `names` (default: the catalog of scene soft, the one every mode runs);
    with edpd, EDPD (not in the catalog) among them, and its --edpd-alpha.  Only those names are
    accepted: any other stops the parser with a message that lists them, before a System is built."""
    names = (list(integrators("soft")) if names is None else list(names)) + (["EDPD"] if edpd else [])
    add_list_argument(parser, "--integrators", default, f"from: {', '.join(names)}", choices=names)
    if edpd:
        parser.add_argument("--edpd-alpha", type=float, default=20.0,
                            help="EDPD's alpha (1/ps); its pair memory grows as alpha falls")


def add_round_arguments(parser, seconds, repeats_help):
    parser.add_argument("--warmup", type=int, default=10, help="untimed steps per integrator")
    parser.add_argument("--steps", type=int, default=None,
                        help="timed steps per measurement (default: about --seconds worth)")
    parser.add_argument("--seconds", type=float, default=seconds,
                        help="target length of one measurement when --steps is not given")
    parser.add_argument("--repeats", type=int, default=3, help=repeats_help)


def add_platform_argument(parser):
    parser.add_argument("--platform", default="CPU", choices=["CPU", "OpenCL", "CUDA"],
                        help="the platform measured (a GPU's at its default precision; --threads does not apply)")


def joined(values):
    return " ".join(map(str, values))
