"""What an option costs an integrator's step: the instability sentinel, Lees-Edwards shear, a
thermostat weight exponent other than 2, thermostat exceptions, transverse friction,
MDPDForce in place of the soft repulsion, and smeared charges.

Scene soft on the CPU platform (or --platform's); each integrator as is and with the option,
alternated --repeats times, medians side by side (the two may differ by less than the noise).

    python3 -m openmmdpd.bench sentinel --sizes 32000 --threads 1 --repeats 9
    python3 -m openmmdpd.bench shear --rate 0.1 --integrators GW S1 --sizes 32000 --threads 1 --repeats 9
    python3 -m openmmdpd.bench shear --pressure-tensor --integrators GW --sizes 1000000 --platform CUDA
    python3 -m openmmdpd.bench weight-exponent --exponent 1 --integrators GW S1 --sizes 32000 --threads 1
    python3 -m openmmdpd.bench exceptions --chain-length 10 --integrators GW S1 --sizes 32000 --threads 1
    python3 -m openmmdpd.bench transverse --friction 4.5 --integrators GW S1 --sizes 32000 --threads 1
    python3 -m openmmdpd.bench mdpd --integrators GW S1 --sizes 32000 256000 --threads 1 2
    python3 -m openmmdpd.bench charges --integrators GW --sizes 32000 --threads 1 2

The exceptions mode excludes the 1-2 pairs of chains of --chain-length consecutive particles
(createThermostatExceptionsFromBonds), as in a polymer melt; the scene's particles are not
moved into chains, which changes which excluded pairs are in range but not the per-pair cost
of looking the exceptions up, which is what the option costs.

The mdpd mode swaps the scene's DPDSoftRepulsionForce (a 25) for Warren's MDPDForce (A -40,
B 25, rd 0.75, rc 1) on the same particles at the same positions, with the same integrator, at
--density 6 (about the MDPD liquid's own) and dt 0.01 by default: at the soft scene's
density 4 the MDPD fluid separates into liquid and voids, and its step would then be timed
with about a third more pairs within rc than the soft fluid's (at density 6, about 8 % fewer).

The charges mode gives a tenth of the beads valences +1 and -1 (alternating) with Slater
smearing (Bjerrum length 1.1, smearing length 0.25; add_smeared_electrostatics), and times
the step with OpenMM's PME for the point charges alone and with the smearing correction
added, each against the uncharged System: PME's share and the correction's.

Shear takes only the integrators that have a shear rate (every one of this plugin's; not
OpenMM's Langevin), by default those of the rates mode.
"""
import statistics

import openmm

from . import DPDSoftRepulsionForce, DPDVVIntegrator, LoweAndersenIntegrator, MDPDForce, ShardlowIntegrator
from .bench_rates import DEFAULT_INTEGRATORS
from .bench_timing import (add_integrators_argument, add_mode, add_platform_argument, add_round_arguments,
                           add_system_arguments, make_context, steps_per_second, timed_steps, waiter, warm_up)
from .catalog import INSTABILITY_THRESHOLD, integrators
from .electrostatics import add_smeared_electrostatics
from .scenes import soft_scene
from .units import KT_TEMPERATURE

SENTINEL_SUMMARY = ("the instability sentinel's cost to GW's step (N 4000 32000, 1 and 2 threads, medians of 3: "
                    "about half a minute)")
WEIGHT_SUMMARY = ("a weight exponent other than 2's cost to each integrator's step (s = 1, 8 integrators, N 4000 "
                  "32000, 1 and 2 threads, medians of 3: about 5 minutes)")
EXCEPTIONS_SUMMARY = ("thermostat exceptions' cost to each integrator's step (the 1-2 pairs of chains of 10 "
                      "excluded, 8 integrators, N 4000 32000, 1 and 2 threads, medians of 3: about 5 minutes)")
TRANSVERSE_SUMMARY = ("transverse friction's cost to each integrator's step (gamma_perp 4.5, the integrators with it, "
                      "N 4000 32000, 1 and 2 threads, medians of 3: about 4 minutes)")
MDPD_SUMMARY = ("MDPDForce's step against DPDSoftRepulsionForce's, same System and integrator at the MDPD liquid's "
                "density (8 integrators, N 4000 32000, 1 and 2 threads, medians of 3: about 5 minutes)")
CHARGES_SUMMARY = ("smeared charges' cost to each integrator's step: PME alone, then PME and the smearing "
                   "correction (a tenth of the beads charged, 8 integrators, N 4000 32000, 1 and 2 threads, medians of 3: "
                   "about 10 minutes)")
SHEAR_SUMMARY = ("Lees-Edwards shear's cost to each integrator's step (rate 0.1, 8 integrators, N 4000 32000, "
                 "1 and 2 threads, medians of 3: about 5 minutes)")
# Estimates: about 1 s per integrator, size, thread count, round and setting (as is and changed),
# plus building each System.
SENTINEL_DURATION = ("With the defaults a run takes about half a minute on 2 cores (an estimate: about 1 s per size, "
                     "thread count, round and setting, off and on, plus building each System); the time grows "
                     "with the sizes and --repeats.")
SHEAR_DURATION = ("With the defaults a run takes about 5 minutes on 2 cores (an estimate: about 1 s per integrator, "
                  "size, thread count, round and setting, unsheared and sheared, plus building each System); the "
                  "time grows with the sizes, the integrators and --repeats.")


def shear_integrators():
    """The names of the catalog (scene soft, as run_shear builds them) whose integrator has a
    shear rate to set: asked of each integrator, so that one added to the catalog is offered
    as soon as it can shear."""
    return [name for name, make in integrators("soft").items() if hasattr(make(0.04), "setShearRate")]


def transverse_integrators():
    """The names of the catalog (scene soft) whose integrator, as the catalog sets it, has
    transverse friction: the velocity-Verlet family, Shardlow and the pair OU method."""
    def has_transverse(integrator):
        if isinstance(integrator, LoweAndersenIntegrator):
            return integrator.getMethod() == LoweAndersenIntegrator.PairOrnsteinUhlenbeck
        return isinstance(integrator, (DPDVVIntegrator, ShardlowIntegrator))
    return [name for name, make in integrators("soft").items() if has_transverse(make(0.04))]


def add_parsers(modes):
    sentinel = add_mode(modes, "sentinel", SENTINEL_SUMMARY, f"GW with the instability threshold off and at "
                        f"{INSTABILITY_THRESHOLD:g} kT, alternated. {SENTINEL_DURATION}", run_sentinel)
    add_cost_arguments(sentinel)
    shear = add_mode(modes, "shear", SHEAR_SUMMARY, f"Each of --integrators unsheared and sheared at --rate, "
                     f"alternated. {SHEAR_DURATION}", run_shear)
    shear.add_argument("--rate", type=float, default=0.1, help="the shear rate (1/ps)")
    shear.add_argument("--pressure-tensor", action="store_true", help="the sheared runs also sample the pressure tensor")
    sheared = shear_integrators()
    add_integrators_argument(shear, [name for name in DEFAULT_INTEGRATORS if name in sheared], names=sheared)
    add_cost_arguments(shear)
    ours = [name for name in DEFAULT_INTEGRATORS if name in sheared]
    weight = add_mode(modes, "weight-exponent", WEIGHT_SUMMARY, f"Each of --integrators with the standard weight "
                      f"(s = 2) and with --exponent, alternated. {SHEAR_DURATION}", run_weight_exponent)
    weight.add_argument("--exponent", type=float, default=1.0, help="the weight exponent s of wD = (1 - r/rc)^s")
    add_integrators_argument(weight, ours, names=sheared)
    add_cost_arguments(weight)
    exceptions = add_mode(modes, "exceptions", EXCEPTIONS_SUMMARY, f"Each of --integrators without and with the "
                          f"exceptions, alternated. {SHEAR_DURATION}", run_exceptions)
    exceptions.add_argument("--chain-length", type=int, default=10, help="beads per chain whose 1-2 pairs are excluded")
    add_integrators_argument(exceptions, ours, names=sheared)
    add_cost_arguments(exceptions)
    transverse = add_mode(modes, "transverse", TRANSVERSE_SUMMARY, f"Each of --integrators without and with transverse "
                          f"friction --friction, alternated. {SHEAR_DURATION}", run_transverse)
    transverse.add_argument("--friction", type=float, default=4.5, help="the transverse friction rate (1/ps)")
    capable = transverse_integrators()
    add_integrators_argument(transverse, [name for name in DEFAULT_INTEGRATORS if name in capable], names=capable)
    add_cost_arguments(transverse)
    mdpd = add_mode(modes, "mdpd", MDPD_SUMMARY, f"Each of --integrators with the soft repulsion and with MDPDForce "
                    f"in its place, alternated. {SHEAR_DURATION}", run_mdpd)
    add_integrators_argument(mdpd, ours, names=sheared)
    add_cost_arguments(mdpd, dt=0.01)
    mdpd.add_argument("--density", type=float, default=6.0, help="the scene's number density")
    charges = add_mode(modes, "charges", CHARGES_SUMMARY, f"Each of --integrators without charges and with them, "
                       f"alternated; PME alone, then with the correction. {SHEAR_DURATION}", run_charges)
    add_integrators_argument(charges, ours, names=sheared)
    add_cost_arguments(charges)


def add_cost_arguments(parser, dt=0.04):
    add_system_arguments(parser, [4000, 32000], [1, 2], dt)
    add_round_arguments(parser, 1.0, "alternated measurements; medians kept")
    add_platform_argument(parser)


def run_sentinel(args):
    print_paired(args, f"scene soft, {args.platform} platform, dt={args.dt:g}; instability threshold 0 (off) and "
                 f"{INSTABILITY_THRESHOLD:g} kT alternated, medians of {args.repeats}", ["GW"],
                 ("steps/s off", "steps/s on"), lambda i, n: i.setInstabilityThreshold(INSTABILITY_THRESHOLD))


def run_shear(args):
    def shear(integrator, n):
        integrator.setShearRate(args.rate)
        integrator.setPressureTensorEnabled(args.pressure_tensor)
    sampled = " with the pressure tensor" if args.pressure_tensor else ""
    print_paired(args, f"scene soft, {args.platform} platform, dt={args.dt:g}; no shear and Lees-Edwards shear at rate "
                 f"{args.rate:g}/ps{sampled} alternated, medians of {args.repeats}", args.integrators,
                 ("steps/s", "steps/s sheared"), shear)


def run_weight_exponent(args):
    print_paired(args, f"scene soft, {args.platform} platform, dt={args.dt:g}; weight exponent 2 and {args.exponent:g} alternated, "
                 f"medians of {args.repeats}", args.integrators, ("steps/s", f"steps/s s={args.exponent:g}"),
                 lambda i, n: i.setDefaultWeightExponent(args.exponent))


def run_exceptions(args):
    def exclude_chain_bonds(integrator, n):
        chains = range(0, n - n % args.chain_length, args.chain_length)
        integrator.createThermostatExceptionsFromBonds(
            [(i, i + 1) for start in chains for i in range(start, start + args.chain_length - 1)], 0.0, 1.0)
    print_paired(args, f"scene soft, {args.platform} platform, dt={args.dt:g}; no exceptions and the 1-2 pairs of chains of "
                 f"{args.chain_length} excluded, alternated, medians of {args.repeats}", args.integrators,
                 ("steps/s", "steps/s excl."), exclude_chain_bonds)


def run_transverse(args):
    print_paired(args, f"scene soft, {args.platform} platform, dt={args.dt:g}; no transverse friction and "
                 f"{args.friction:g}/ps alternated, medians of {args.repeats}", args.integrators,
                 ("steps/s", "steps/s perp."), lambda i, n: i.setDefaultTransverseFriction(args.friction))


def with_mdpd(system):
    """A copy of `system` with its DPDSoftRepulsionForce replaced by Warren's MDPDForce."""
    copy = openmm.XmlSerializer.clone(system)
    soft = [k for k, force in enumerate(copy.getForces()) if isinstance(force, DPDSoftRepulsionForce)]
    copy.removeForce(soft[0])
    copy.addForce(MDPDForce(-40.0, 25.0, 1.0, 0.75))
    return copy


def run_mdpd(args):
    print_paired(args, f"scene soft at density {args.density:g}, {args.platform} platform, dt={args.dt:g}; "
                 f"DPDSoftRepulsionForce (a 25) and MDPDForce (A -40, B 25, rd 0.75) alternated, medians of {args.repeats}",
                 args.integrators, ("steps/s soft", "steps/s MDPD"), lambda i, n: None, with_mdpd, args.density)


def with_charges(correction):
    """A function giving a copy of a System a tenth of its beads charged +1/-1 (Slater smearing),
    with the smearing correction or with PME's point charges alone."""
    def charged(system):
        copy = openmm.XmlSerializer.clone(system)
        valences = [(1 if k % 20 == 0 else -1) if k % 10 == 0 else 0 for k in range(copy.getNumParticles())]
        added = add_smeared_electrostatics(copy, valences, 1.1, 0.25)
        if not correction:
            copy.removeForce([k for k, f in enumerate(copy.getForces()) if isinstance(f, openmm.CustomNonbondedForce)][-1])
        del added
        return copy
    return charged


def run_charges(args):
    for correction, what in ((False, "PME's point charges"), (True, "PME and the smearing correction")):
        print_paired(args, f"scene soft, {args.platform} platform, dt={args.dt:g}; uncharged and {what} (10 % of the beads, "
                     f"Slater, l_B 1.1, lambda 0.25) alternated, medians of {args.repeats}", args.integrators,
                     ("steps/s", "steps/s charged"), lambda i, n: None, with_charges(correction))


def print_paired(args, title, names, columns, change, change_system=None, density=4.0):
    print(title)
    print(f"{'integrator':>10} {'N':>6} {'threads':>7}  {columns[0]:>14} {columns[1]:>14}  {'cost':>8}")
    for name in names:
        for n in args.sizes:
            for threads in args.threads:
                plain, changed, cost = measure_paired(n, threads, args, name, change, change_system, density)
                print(f"{name:>10} {n:>6} {threads:>7}  {plain:>14.2f} {changed:>14.2f}  {100 * cost:>+7.2f}%")


def measure_paired(n, threads, args, name, change, change_system=None, density=4.0):
    """Integrator `name` on scene soft at `density` as is and with change(integrator, n) applied
    (and the System replaced by change_system(system), if given), alternated: (median steps/s as
    is, median changed, median of the per-round cost changed/as-is - 1)."""
    scene = soft_scene(num_particles=n, density=density)
    runs = []
    for changed in (False, True):
        integrator = integrators("soft")[name](args.dt)  # the scene's catalog: OC has its averages
        system = scene.system
        if changed:
            change(integrator, n)
            system = change_system(system) if change_system else system
        context = make_context(system, integrator, threads, args)
        context.setPositions(scene.positions)
        context.setVelocitiesToTemperature(KT_TEMPERATURE, 1)
        wait = waiter(context, args)
        runs.append((context, wait, integrator, timed_steps(warm_up(integrator, args, wait), args)))
    plain, changed = [], []
    for _ in range(args.repeats):
        for rates, (_, wait, integrator, steps) in zip((plain, changed), runs):
            rates.append(steps_per_second(integrator, steps, wait))
    cost = statistics.median(a / b - 1 for a, b in zip(plain, changed))
    return statistics.median(plain), statistics.median(changed), cost
