"""λ-phage DNA as a 5-bead worm-like chain under Lees–Edwards shear (Symeonidis and Karniadakis
2006, §8, Figs. 12–13), on the scene `wlc-shear` (4000 particles in 10 x 20 x 5, a = 18.75).

    PYTHONPATH=build/python nice -n 10 /usr/bin/python3 examples/wlc_shear.py [--quick] [--tau 4.2]

(a) The chain's relaxation time tau (Fig. 12): the chain starts 30 % extended (straight along
    y; there is no flow), in a solvent equilibrated beforehand, from --starts independent
    starts (velocities and random numbers), with Lowe–Andersen (non-staggered, Gamma 4.5,
    dt 0.01). The mean-square extension <x^2>(t) (x: the chain's extent along the stretch) is
    averaged over the starts and <x^2>_0 + A exp(-t/tau) fitted to its tail (t past the point
    where the excess has halved); the error of tau is the jackknife over the starts.  Paper
    002's own estimate, the area under the excess over its initial value, is given beside it.
(b) The mean fractional extension <x>/L in the flow direction (x: the chain's largest extent
    along x, L its contour length) against Wi = rate tau (Fig. 13), with the staggered
    integrator's Lowe base (Symeonidis and Karniadakis' recommended (mu, a, b) = (0, 0, 0.4), Gamma 4.5) and
    velocity-Verlet base ((0, 0.6, 0), lambda 0.65, gamma 4.5), K = 1, 6, 10 at the sub-step
    dt = 0.01 (Dt = K dt).  Each run starts from the equilibrated solvent with the imposed
    linear flow already in the velocities, discards --settle tau, then samples every 0.1 time
    units; the error is from 10 block means.  The Underhill–Doyle ratio of the springs is
    refreshed from the chain's extension at every sample (Symeonidis and Karniadakis: every step).

Writes tau.csv, extension.csv, relaxation.png, extension.png and results.md under --out.
CPU platform, --threads 1 by default: the machine it was written on is shared.
"""
import argparse
import csv
import json
import os
import time

import numpy as np
import openmm
from openmm import unit

import openmmdpd
from openmmdpd import scenes, shear
from openmmdpd.analysis import block_average
from openmmdpd.units import KT_TEMPERATURE

L_SPRING, BEADS, FRICTION, DT = 8.0, 5, 4.5, 0.01
CONTOUR = L_SPRING * (BEADS - 1)
SAMPLE = 0.1   # time between samples (ps = DPD time units)
SCHEMES = [("lowe", 1), ("lowe", 6), ("lowe", 10), ("vv", 1), ("vv", 6), ("vv", 10)]


def context_for(scene, integrator, args):
    platform = openmm.Platform.getPlatformByName(args.platform)
    properties = {"Threads": str(args.threads)} if args.platform == "CPU" else {}
    return openmm.Context(scene.system, integrator, platform, properties)


def lowe(seed):
    integrator = openmmdpd.LoweAndersenIntegrator(KT_TEMPERATURE, FRICTION, 1.0, DT)
    integrator.setRandomNumberSeed(seed)
    return integrator


def groot_warren(seed):
    """The velocity-Verlet base unstaggered: GW with lambda 0.65, gamma 4.5, dt 0.01."""
    integrator = openmmdpd.DPDVVIntegrator(KT_TEMPERATURE, FRICTION, 1.0, DT)
    integrator.setLambda(0.65)
    integrator.setRandomNumberSeed(seed)
    return integrator


def staggered(base, k, seed):
    integrator = openmmdpd.StaggeredDPDIntegrator(KT_TEMPERATURE, FRICTION, 1.0, k * DT, k)
    integrator.setBaseScheme(openmmdpd.StaggeredDPDIntegrator.LoweAndersen if base == "lowe"
                             else openmmdpd.StaggeredDPDIntegrator.VelocityVerlet)
    integrator.useRecommendedParameters()
    integrator.setRandomNumberSeed(seed)
    return integrator


def equilibrate(scene, args):
    """Positions after --equilibrate time units of Lowe from the scene's random start."""
    context = context_for(scene, lowe(7), args)
    context.setPositions(scene.positions)
    context.setVelocitiesToTemperature(KT_TEMPERATURE, 7)
    context.getIntegrator().step(round(args.equilibrate / DT))
    return context.getState(getPositions=True).getPositions(asNumpy=True).value_in_unit(unit.nanometer)


def stretched_chain(box, fraction):
    """A straight chain along y through the box centre, its ends fraction * L apart."""
    y = (np.arange(BEADS) - (BEADS - 1) / 2) * fraction * L_SPRING
    return np.column_stack([np.full(BEADS, box[0] / 2), box[1] / 2 + y, np.full(BEADS, box[2] / 2)])


def chain_positions(context):
    state = context.getState(getPositions=True)
    return state.getPositions(asNumpy=True)[:BEADS].value_in_unit(unit.nanometer)


def relaxation_run(scene, solvent, start, args):
    """<extent along y>^2 every SAMPLE over --relax-time, from the 30 %-extended chain."""
    box = np.diag([v.value_in_unit(unit.nanometer) for v in scene.system.getDefaultPeriodicBoxVectors()])
    positions = solvent.copy()
    positions[:BEADS] = stretched_chain(box, 0.3)
    make = lowe if args.tau_scheme == "lowe" else groot_warren
    context = context_for(scene, make(100 + start), args)
    context.setPositions(positions)
    context.setVelocitiesToTemperature(KT_TEMPERATURE, 200 + start)
    samples = []
    for _ in range(round(args.relax_time / SAMPLE) + 1):
        chain = chain_positions(context)
        scenes.update_persistence_ratio(context, chain, CONTOUR, axis=1)
        samples.append((scenes.fractional_extension(chain, CONTOUR, axis=1) * CONTOUR) ** 2)
        context.getIntegrator().step(round(SAMPLE / DT))
    return np.array(samples)


def fit_tail(t, x2):
    """(tau, baseline, amplitude) of baseline + amplitude exp(-t/tau) fitted where the excess over
    the last quarter's mean has fallen below half its initial value."""
    from scipy.optimize import curve_fit
    baseline = x2[3 * len(x2) // 4:].mean()
    below = np.nonzero(x2 - baseline < 0.5 * (x2[0] - baseline))[0]
    tail = below[0] if len(below) else 0  # a run too short to halve (--quick): the whole curve
    model = lambda t, c, a, tau: c + a * np.exp(-t / tau)  # noqa: E731
    (c, a, tau), _ = curve_fit(model, t[tail:], x2[tail:], p0=(baseline, x2[0] - baseline, t[tail] + 1.0),
                               maxfev=20000)
    return tau, c, a


def area_tau(t, x2, baseline):
    """Symeonidis and Karniadakis': the area under the excess <x^2> - <x^2>_0, over its initial value."""
    excess = x2 - baseline
    return float(np.sum(0.5 * (excess[1:] + excess[:-1]) * np.diff(t)) / excess[0])


def measure_tau(scene, solvent, args, out):
    runs = np.array([relaxation_run(scene, solvent, s, args) for s in range(args.starts)])
    t = np.arange(runs.shape[1]) * SAMPLE
    mean = runs.mean(axis=0)
    tau, baseline, amplitude = fit_tail(t, mean)
    jack = np.array([fit_tail(t, np.delete(runs, s, axis=0).mean(axis=0))[0] for s in range(len(runs))])
    error = float(np.sqrt((len(jack) - 1) * np.mean((jack - jack.mean()) ** 2)))
    result = {"tau": tau, "tau_error": error, "baseline": baseline, "amplitude": amplitude,
              "area_tau": area_tau(t, mean, baseline), "starts": len(runs), "time": float(t[-1])}
    with open(os.path.join(out, "tau.csv"), "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(["t", "mean_x2", "sem_x2"])
        sem = runs.std(axis=0, ddof=1) / np.sqrt(len(runs))
        writer.writerows(zip(t.round(6), mean, sem))
    plot_relaxation(t, mean, runs.std(axis=0, ddof=1) / np.sqrt(len(runs)), result, out)
    with open(os.path.join(out, "tau.json"), "w") as f:
        json.dump(result, f, indent=1)
    return result


def plot_relaxation(t, mean, sem, result, out):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6, 4))
    ax.errorbar(t, mean, yerr=sem, fmt=".", ms=3, alpha=0.5, label=f"mean of {result['starts']} starts")
    ax.plot(t, result["baseline"] + result["amplitude"] * np.exp(-t / result["tau"]), "r-",
            label=f"fit: tau = {result['tau']:.2f} ± {result['tau_error']:.2f}")
    ax.set(xlabel="t (DPD time)", ylabel="<x²> (rc²)", title="wlc-shear: relaxation of a 30 %-extended chain")
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(out, "relaxation.png"), dpi=120)
    plt.close(fig)


def sheared_run(scene, solvent, base, k, rate, args, seed):
    """<x>/L (block mean, error), peculiar kT of the solvent, samples and wall seconds."""
    integrator = staggered(base, k, seed)
    integrator.setShearRate(rate)
    context = context_for(scene, integrator, args)
    context.setPositions(solvent)
    context.setVelocitiesToTemperature(KT_TEMPERATURE, seed)
    height = scene.system.getDefaultPeriodicBoxVectors()[1][1].value_in_unit(unit.nanometer)
    v = context.getState(getVelocities=True).getVelocities(asNumpy=True).value_in_unit(unit.nanometer / unit.picosecond)
    v[:, 0] += shear.streaming_velocity(solvent[:, 1], rate, height)  # the steady flow from the start
    context.setVelocities(v)
    every = max(1, round(SAMPLE / (k * DT)))
    started = time.time()
    integrator.step(round(args.settle * args.tau / (k * DT)))
    extension, kT = [], []
    for _ in range(round(args.sample_time / SAMPLE)):
        integrator.step(every)
        chain = chain_positions(context)
        scenes.update_persistence_ratio(context, chain, CONTOUR, axis=0)
        extension.append(scenes.fractional_extension(chain, CONTOUR, axis=0))
    state = context.getState(getPositions=True, getVelocities=True)
    kT.append(shear.peculiar_temperature(state.getPositions(asNumpy=True), state.getVelocities(asNumpy=True),
                                         np.ones(len(solvent)), rate, height)[0])
    mean, error = block_average(extension, 10)
    return mean, error, len(extension), kT[0], time.time() - started


def measure_extension(scene, solvent, args, out):
    rows = []
    path = os.path.join(out, "extension.csv")
    for wi in args.wi:
        rate = wi / args.tau
        for n, (base, k) in enumerate(SCHEMES if not args.schemes else [parse_scheme(s) for s in args.schemes]):
            mean, error, samples, kT, seconds = sheared_run(scene, solvent, base, k, rate, args, 1000 + n)
            rows.append({"base": base, "K": k, "Dt": round(k * DT, 6), "Wi": wi, "rate": round(rate, 6),
                         "extension": mean, "error": error, "samples": samples, "peculiar_kT_end": kT,
                         "seconds": round(seconds, 1)})
            print(f"Wi {wi:5.2f} rate {rate:.4f} {base:4s} K {k:2d}: <x>/L = {mean:.4f} ± {error:.4f} "
                  f"(kT {kT:.3f}, {seconds:.0f} s)", flush=True)
            write_rows(path, rows)
    return rows


def parse_scheme(text):
    base, k = text.split("-")
    return base, int(k)


def write_rows(path, rows):
    with open(path, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)


def plot_extension(rows, out):
    import matplotlib.pyplot as plt
    from openmmdpd.charts import legend_outside, log_axis, save
    fig, ax = plt.subplots(figsize=(6, 4))
    for (base, k) in sorted({(r["base"], r["K"]) for r in rows}):
        mine = [r for r in rows if r["base"] == base and r["K"] == k]
        ax.errorbar([r.get("Wi_own", r["Wi"]) * (1 + 0.02 * k) for r in mine], [r["extension"] for r in mine],
                    yerr=[r["error"] for r in mine], marker="o" if base == "lowe" else "s", capsize=3,
                    linestyle="-" if base == "lowe" else "--", label=f"{'Lowe' if base == 'lowe' else 'vV'} K = {k}")
    log_axis(ax)
    ax.set(xlabel="Wi = rate tau (each base's own tau)" if "Wi_own" in rows[0] else "Wi = rate tau", ylabel="<x>/L",
           title="wlc-shear: mean fractional extension")
    legend_outside(ax, fontsize=8)
    save(fig, os.path.join(out, "extension.png"), dpi=120)


def read_rows(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    for r in rows:
        for key in r:
            if key != "base":
                r[key] = float(r[key])
        r["K"], r["samples"] = int(r["K"]), int(r["samples"])
    return rows


def report_only(args):
    """The chart and table again from the files of an earlier (possibly interrupted) run."""
    path = os.path.join(args.out, "tau.json")
    tau = None
    if os.path.exists(path):
        with open(path) as f:
            tau = json.load(f)
    rows = read_rows(os.path.join(args.out, "extension.csv"))
    # The vV base's solvent (gamma 4.5) is not Lowe's (Gamma 4.5): with its own tau, if measured
    # (--tau-scheme vv --out OUT/tau-vv), its rows get their own Weissenberg numbers.
    path = os.path.join(args.out, "tau-vv", "tau.json")
    if tau is not None and os.path.exists(path):
        with open(path) as f:
            tau["vv"] = json.load(f)
        for r in rows:
            r["Wi_own"] = r["rate"] * (tau["vv"]["tau"] if r["base"] == "vv" else tau["tau"])
    plot_extension(rows, args.out)
    write_markdown(tau, rows, args, args.out)


def write_markdown(tau, rows, args, out):
    lines = ["# wlc-shear: 5-bead worm-like chain (λ-DNA) under shear (Symeonidis and Karniadakis 2006, §8)", "",
             f"Generated by `examples/wlc_shear.py {' '.join(args.argv)}`.", ""]
    if tau is not None:
        lines += [f"Relaxation time (Fig. 12): tau = {tau['tau']:.3f} ± {tau['tau_error']:.3f} (exponential fit to "
                  f"the tail, jackknife over {tau['starts']} starts of {tau['time']:.0f} time units; "
                  f"<x²>_0 = {tau['baseline']:.3f}); Symeonidis and Karniadakis' area estimate {tau['area_tau']:.3f}.", ""]
    else:
        lines += [f"tau = {args.tau} (given, not measured in this run).", ""]
    if tau is not None and "vv" in tau:
        lines += [f"With the vV base's solvent (GW, lambda 0.65, gamma 4.5, dt 0.01): tau = {tau['vv']['tau']:.3f} ± "
                  f"{tau['vv']['tau_error']:.3f} ({tau['vv']['starts']} starts; area estimate {tau['vv']['area_tau']:.3f}). "
                  "Wi is rate x Lowe's tau for every row; 'own Wi' uses each base's own tau.", ""]
    if rows:
        own = "Wi_own" in rows[0]
        lines += ["| Wi | " + ("own Wi | " if own else "") + "rate | base | K | Dt | <x>/L | error | samples | "
                  "peculiar kT (end) |", "|---|" + ("---|" if own else "") + "---|---|---|---|---|---|---|---|"]
        lines += [f"| {r['Wi']} | " + (f"{r['Wi_own']:.2f} | " if own else "") + f"{r['rate']:.4f} | {r['base']} | "
                  f"{r['K']} | {r['Dt']} | {r['extension']:.4f} | {r['error']:.4f} | {r['samples']} | "
                  f"{r['peculiar_kT_end']:.3f} |" for r in rows]
    with open(os.path.join(out, "results.md"), "w") as f:
        f.write("\n".join(lines) + "\n")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="a smoke run: tiny times, one Wi, two schemes")
    parser.add_argument("--out", default="docs/results/wlc-shear")
    parser.add_argument("--platform", default="CPU")
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--equilibrate", type=float, default=5.0, help="solvent equilibration (time units)")
    parser.add_argument("--starts", type=int, default=8, help="independent relaxation runs")
    parser.add_argument("--relax-time", type=float, default=30.0, help="time units per relaxation run")
    parser.add_argument("--tau", type=float, help="skip (a): use this relaxation time")
    parser.add_argument("--tau-scheme", choices=["lowe", "vv"], default="lowe",
                        help="(a) with Lowe (as Symeonidis and Karniadakis) or GW lambda 0.65 (the vV base's solvent and viscosity)")
    parser.add_argument("--wi", type=float, nargs="+", default=[0.5, 1.0, 2.0, 4.0])
    parser.add_argument("--schemes", nargs="+", help="e.g. lowe-1 vv-6 (default: Lowe and vV, K = 1, 6, 10)")
    parser.add_argument("--settle", type=float, default=2.0, help="discarded before sampling (in tau)")
    parser.add_argument("--sample-time", type=float, default=100.0, help="time units sampled per run")
    parser.add_argument("--skip-extension", action="store_true", help="(a) only")
    parser.add_argument("--report", action="store_true", help="no run: chart and table from --out's files")
    args = parser.parse_args(argv)
    args.argv = argv if argv is not None else __import__("sys").argv[1:]
    if args.quick:
        args.equilibrate, args.starts, args.relax_time, args.sample_time = 0.5, 2, 2.0, 2.0
        args.wi, args.schemes = [1.0], args.schemes or ["lowe-6", "vv-6"]
    os.makedirs(args.out, exist_ok=True)
    if args.report:
        return report_only(args)
    scene = scenes.build_scene("wlc-shear", l_spring=L_SPRING)
    solvent = equilibrate(scene, args)
    tau = None
    if args.tau is None:
        tau = measure_tau(scene, solvent, args, args.out)
        args.tau = tau["tau"]
        print(f"tau = {tau['tau']:.3f} ± {tau['tau_error']:.3f} (area estimate {tau['area_tau']:.3f})", flush=True)
    rows = [] if args.skip_extension else measure_extension(scene, solvent, args, args.out)
    if rows:
        plot_extension(rows, args.out)
    write_markdown(tau, rows, args, args.out)


if __name__ == "__main__":
    main()
