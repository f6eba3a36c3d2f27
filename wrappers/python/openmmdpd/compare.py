"""The main job: every integrator on a scene over a sweep of time steps, measured for
accuracy and for cost in the same run, with charts, the CSV behind them and a report.

    /usr/bin/python3 -m openmmdpd.compare [--scene soft] [--out results/compare-soft]

Every run starts from the same configuration, equilibrated with LangevinMiddleIntegrator
at a small dt, and samples the same simulated time (--time), so that every dt gets the same
statistics.  Per run: kinetic <kT> (3N - 3 dof), configurational temperature (scene soft),
chain <kT>, Rg and the longest bond (polymer), each mean with its standard error from the
statistical inefficiency (pymbar); g(r) (MDAnalysis InterRDF on frames held in memory) and
its deviation from the same integrator at the smallest dt (and from 1 on `ideal`); the
coordination number Nc to the first minimum r1 (both with errors from blocks of frames)
and at the fixed radii 1.0 and 1.16; the dynamics (openmmdpd.dynamics): tracer diffusion D
from the MSD (MDAnalysis EinsteinMSD), the shear viscosity eta from a short sheared run, the
Schmidt number and the transverse-current viscosity, each against the same model's dt -> 0
limit, and the cheapest usable run; and the cost: the time of a step relative to a LangevinMiddleIntegrator step
on the same System at the same dt, timed in alternating blocks and repeated (median and
its spread), besides the raw seconds.  A run is stable only if it does not blow up, does
not pass the instability threshold (40 kT by default: a transient blow-up that would
otherwise recover and go into the averages), has <kT> in [0.5, 1.5], on scene soft has a
configurational kT within 10 % of 1 and no overlapping particles (g(r < 0.2) more than 0.2
above that of the smallest dt), and on scene polymer has a chain <kT> within 10 % of 1 and
no bond longer than 2.5; an unstable run is recorded with its reason, not raised.
"""
import csv
import math
import os
import re
import sys
import time

import numpy as np
import openmm
from openmm import unit
from scipy.spatial import cKDTree

from .analysis import (frame_radial_distributions, grouped_squared_displacement, median_with_error, radius_of_gyration,
                       ratio_with_error, standard_error)
from . import dynamics, options
from .catalog import CUTOFF, FRICTION, INSTABILITY_THRESHOLD, integrators
from .charts import use_file_backend
from .protocol import (BOND_LIMIT, CHAIN_KT_TOLERANCE, CONF_KT_TOLERANCE, CORE_RADIUS, DIFFUSION_FIT,
                       DIFFUSION_GROUPS, OVERLAP_EXCESS, R1_BLOCKS, schedule)
from .report import read_gr, read_rows, write_report
from .scenes import SCENES, build_scene
from .units import KT_TEMPERATURE

G_R_MAX, G_BIN = 2.0, 0.025  # g(r) to 2 rc (or half the box) in bins of 0.025 rc
FIXED_RADII = (1.0, 1.16)  # Nc at these radii: r1 sits on a minimum too flat to integrate to
COLUMNS = ["scene", "integrator", "dt", "status", "reason", "steps", "kT", "kT_err", "kT_error", "kT_conf",
           "kT_conf_err", "g_core", "g_dev_ref", "g_dev_ideal", "Nc", "Nc_err", "r1", "r1_err", "Nc_1.0",
           "Nc_1.0_err", "Nc_1.16", "Nc_1.16_err", "D", "D_err", "eta", "eta_err", "Sc", "Sc_err", "eta_T",
           "eta_T_err", "D_rel", "D_rel_err", "eta_rel", "eta_rel_err", "Sc_rel", "Sc_rel_err", "eta_T_rel",
           "eta_T_rel_err", "usable", "chain_kT", "chain_kT_err", "Rg", "Rg_err", "bond_max", "cost_ratio",
           "cost_ratio_err", "cost_per_time", "cost_per_time_err", "cpu_s_per_time", "wall_s_per_time",
           "langevin_cpu_s_per_time", "note"]


# --- observables ------------------------------------------------------------------------------

def _box_length(system):
    return system.getDefaultPeriodicBoxVectors()[0][0].value_in_unit(unit.nanometer)


def g_r_range(length):
    """(r_max, bins) of g(r) in a box of side length: to G_R_MAX, or half the box if smaller."""
    bins = int(min(G_R_MAX, length / 2) / G_BIN + 1e-9)
    return bins * G_BIN, bins


def g_r_centres(system):
    """The centres of the g(r) bins of run_one in the system's box (see g_r_range)."""
    r_max, bins = g_r_range(_box_length(system))
    return (np.arange(bins) + 0.5) * (r_max / bins)


def coordination_at(r, g, radius, density):
    """Nc(R) = 4 pi rho int_0^R g r^2 dr, g constant within each bin (so the ideal gas gives
    exactly 4/3 pi R^3 rho); g may hold one row per frame (one Nc per row)."""
    half = 0.5 * (r[1] - r[0])
    below = np.clip(radius, r - half, r + half)  # the part of each bin inside R
    return density * (np.asarray(g) * (4 / 3 * np.pi * (below ** 3 - (r - half) ** 3))).sum(axis=-1)


def first_minimum(r, g):
    """r1, the first minimum after the main peak; nan without structure (ideal gas).

    The minimum of a soft fluid's g(r) is shallow and broad: it is located on g smoothed
    over 9 bins (0.2 rc), within 0.8 rc after the peak, and refined by a parabola through
    the three bins around it.  The peak is looked for beyond r = 0.5: closer in, a soft
    fluid's g only rises, and the few pairs there make an ideal gas's g noisy enough to
    look like a peak.
    """
    smooth = np.convolve(g, np.ones(9) / 9, mode="same")
    dr = r[1] - r[0]
    peak = int(0.5 / dr) + int(np.argmax(smooth[int(0.5 / dr):]))
    window = np.arange(peak + 1, min(len(g) - 5, peak + int(0.8 / dr)))
    if smooth[peak] < 1.02 or len(window) == 0:
        return float("nan")
    k = int(window[np.argmin(smooth[window])])
    y0, y1, y2 = smooth[k - 1], smooth[k], smooth[k + 1]
    curvature = y0 - 2 * y1 + y2
    return float(r[k] + (0.5 * dr * (y0 - y2) / curvature if curvature > 0 else 0.0))


def coordination_number(r, g, density):
    """Nc = 4 pi rho int_0^r1 g r^2 dr to the first minimum r1 itself (not to a bin edge)."""
    return float(coordination_at(r, g, first_minimum(r, g), density))


def _spread(values):
    """Standard error of the mean of independent block values (nan for fewer than 2)."""
    values = np.asarray(values, dtype=float)
    values = values[np.isfinite(values)]
    return float(values.std(ddof=1) / np.sqrt(len(values))) if len(values) > 1 else float("nan")


def shell_structure(r, frame_g, density):
    """(g, {Nc, Nc_err, r1, r1_err, Nc_1.0, Nc_1.0_err, ...}) from g(r) of each frame (rows).

    r1 and Nc(r1) get their errors from the spread of R1_BLOCKS consecutive blocks of frames;
    Nc at the fixed radii from its per-frame series (statistical inefficiency).
    """
    frame_g = np.asarray(frame_g, dtype=float)
    g = frame_g.mean(axis=0)
    r1 = first_minimum(r, g)
    block_g = [block.mean(axis=0) for block in np.array_split(frame_g, min(R1_BLOCKS, len(frame_g)))]
    block_r1 = [first_minimum(r, gb) for gb in block_g]
    shells = dict(r1=r1, r1_err=_spread(block_r1), Nc=float(coordination_at(r, g, r1, density)),
                  Nc_err=_spread([coordination_at(r, gb, x, density) for gb, x in zip(block_g, block_r1)]))
    for radius in FIXED_RADII:
        series = coordination_at(r, frame_g, radius, density)
        shells[f"Nc_{radius}"], shells[f"Nc_{radius}_err"] = float(series.mean()), standard_error(series)
    return g, shells


def soft_repulsion_laplacian(positions, length, a=25.0, rc=CUTOFF):
    """sum_i |F_i|^2 and sum_i lap_i U for U = a rc (1 - r/rc)^2 / 2 (configurational kT)."""
    tree = cKDTree(np.mod(positions, length), boxsize=length)
    pairs = tree.query_pairs(rc, output_type="ndarray")
    d = positions[pairs[:, 0]] - positions[pairs[:, 1]]
    d -= length * np.round(d / length)
    r = np.sqrt((d * d).sum(axis=1))
    keep = r > 0
    pairs, d, r = pairs[keep], d[keep], r[keep]
    fmag = a * (1 - r / rc)  # -U'(r)
    f = d * (fmag / r)[:, None]
    forces = np.zeros_like(positions)
    np.add.at(forces, pairs[:, 0], f)
    np.add.at(forces, pairs[:, 1], -f)
    # lap U for one pair, seen from either particle: U'' + 2 U'/r = a/rc - 2 a (1 - r/rc)/r
    lap = 2 * (a / rc - 2 * fmag / r).sum()
    return (forces * forces).sum(), lap


def diffusion(times, msd):
    """D = slope / 6 of an MSD averaged over time origins, fitted over the lags of DIFFUSION_FIT
    (time units), or a quarter to half of a run too short for them: a window fixed in time, so
    that a longer run has more origins per lag and a better D (long lags have few origins,
    short ones may be ballistic)."""
    times = np.asarray(times, dtype=float)
    start, end = min(DIFFUSION_FIT[0], times[-1] / 4), min(DIFFUSION_FIT[1], times[-1] / 2)
    fit = (times >= start - 1e-9) & (times <= end + 1e-9)
    if fit.sum() < 2:
        return float("nan")
    return float(np.polyfit(times[fit], np.asarray(msd)[fit], 1)[0] / 6)


def diffusion_with_error(times, msd, group_msd):
    """D of the MSD and its standard error from the spread of the groups' own D.  Momentum
    conservation correlates the groups weakly (the centre of mass stays put), which this
    error leaves out."""
    per_group = [diffusion(times, group_msd[:, g]) for g in range(group_msd.shape[1])]
    return diffusion(times, msd), standard_error(per_group)


# --- stability --------------------------------------------------------------------------------

def mark_unstable(row, reason, note):
    row.update(status="unstable", reason=reason, note=note)


def failure_reason(message):
    """Why a run that stopped with this message is unstable: the instability sentinel, or a
    blow-up (a non-finite value, a particle jumping cutoffs, a sampled kT above 10)."""
    return "sentinel" if "instability threshold" in message else "blow-up"


def judge(row, scene):
    """Marks a completed run on the scene called `scene` unstable if its <kT> is outside
    [0.5, 1.5]; on soft, if its configurational kT is more than 10 % from 1; on polymer, if
    its chain <kT> is more than 10 % from 1 or a bond was ever longer than BOND_LIMIT."""
    if not 0.5 <= row["kT"] <= 1.5:
        mark_unstable(row, "kT", f"<kT> = {row['kT']:.3g}, outside [0.5, 1.5]")
    elif scene == "soft" and abs(row["kT_conf"] - 1) > CONF_KT_TOLERANCE:
        mark_unstable(row, "kT_conf", f"configurational kT = {row['kT_conf']:.3g}, more than 10 % from 1")
    elif scene == "polymer" and abs(row["chain_kT"] - 1) > CHAIN_KT_TOLERANCE:
        mark_unstable(row, "chain_kT", f"chain <kT> = {row['chain_kT']:.3g}, more than 10 % from 1")
    elif scene == "polymer" and row["bond_max"] > BOND_LIMIT:
        mark_unstable(row, "bond", f"a bond reached {row['bond_max']:.3g}, longer than {BOND_LIMIT:g}")


def judge_overlaps(rows):
    """Marks unstable the stable runs with overlapping particles: g(r < CORE_RADIUS) more than
    OVERLAP_EXCESS above the reference, the median over integrators of g(r < CORE_RADIUS) at
    the smallest dt with stable runs (each integrator's own smallest dt could itself overlap)."""
    ok = [row for row in rows if row["status"] == "ok" and math.isfinite(row["g_core"])]
    if not ok:
        return
    smallest = min(row["dt"] for row in ok)
    reference = float(np.median([row["g_core"] for row in ok if row["dt"] == smallest]))
    for row in ok:
        if row["g_core"] > reference + OVERLAP_EXCESS:
            mark_unstable(row, "overlap", f"overlapping particles: g(r < {CORE_RADIUS:g}) = {row['g_core']:.3g}, "
                                          f"{reference:.3g} at dt {smallest:g}")


# --- one run ----------------------------------------------------------------------------------

class Sampler:
    """One run's time series, taken every `stride` steps, and its frames (positions for g(r)
    and the MSD, configurational temperature) every `frame_every` samples."""

    def __init__(self, scene, a):
        self.n, self.length = scene.system.getNumParticles(), _box_length(scene.system)
        self.scene = scene.name
        self.a = a
        self.chain = np.array(scene.chain_particles[0]) if scene.chain_particles else None
        self.masses = np.array([scene.system.getParticleMass(i)._value for i in range(self.n)])
        self.kT, self.chain_kT, self.rg, self.bond_max, self.force2, self.laplacian = [], [], [], [], [], []
        self.frames, self.currents = [], []

    def sample(self, pos, vel):
        """Records one sample; returns its kinetic kT."""
        v2 = (vel * vel).sum(axis=1)  # unit masses
        self.kT.append(v2.sum() / (3 * self.n - 3))
        self.currents.append(dynamics.transverse_currents(pos, vel, self.masses, self.length))
        if self.chain is not None:
            self.chain_kT.append(v2[self.chain].sum() / (3 * len(self.chain)))
            self.rg.append(radius_of_gyration(pos[self.chain]))
            bonds = np.diff(pos[self.chain], axis=0)
            bonds -= self.length * np.round(bonds / self.length)
            self.bond_max.append(float(np.sqrt((bonds * bonds).sum(axis=1)).max()))
        return self.kT[-1]

    def frame(self, pos):
        self.frames.append(pos)
        if self.scene == "soft":  # the one scene whose whole potential is the soft repulsion
            f2, lap = soft_repulsion_laplacian(pos, self.length, self.a)
            self.force2.append(f2)
            self.laplacian.append(lap)

    def mass_density(self):
        return self.masses.sum() / self.length ** 3

    def summarise(self, row, sample_time, frame_time, gr_frames):
        """Puts the observables and their standard errors in row; returns g(r) (None without frames)."""
        kT = np.array(self.kT)
        row.update(kT=kT.mean(), kT_err=standard_error(kT), kT_error=abs(kT.mean() - 1))
        row["eta_T"], row["eta_T_err"] = dynamics.transverse_viscosity(self.currents, sample_time, self.mass_density(),
                                                                       self.length)
        if self.force2:
            row["kT_conf"], row["kT_conf_err"] = ratio_with_error(self.force2, self.laplacian)
        if self.chain_kT:
            row.update(chain_kT=float(np.mean(self.chain_kT)), chain_kT_err=standard_error(self.chain_kT),
                       Rg=float(np.mean(self.rg)), Rg_err=standard_error(self.rg), bond_max=max(self.bond_max))
        if len(self.frames) < 2:
            return None
        frames = np.array(self.frames)
        msd = grouped_squared_displacement(frames, frame_time, DIFFUSION_GROUPS)
        row["D"], row["D_err"] = diffusion_with_error(*msd)
        # g(r) of gr_frames frames spread evenly over the run: InterRDF costs ~10 pair searches of cKDTree's
        chosen = np.unique(np.linspace(0, len(frames) - 1, gr_frames).round().astype(int))
        r, frame_g = frame_radial_distributions(frames[chosen], self.length, *g_r_range(self.length))
        g, shells = shell_structure(r, frame_g, self.n / self.length ** 3)
        row.update(shells, g_core=float(g[r < CORE_RADIUS].mean()))
        if self.scene == "ideal":
            row["g_dev_ideal"] = float(np.sqrt(np.mean((g[r > 0.1] - 1) ** 2)))
        return g


def _platform(args):
    properties = {"Threads": str(args.threads)} if args.platform == "CPU" else {}
    return openmm.Platform.getPlatformByName(args.platform), properties


PREPARE_DT = 0.005


def equilibrated_positions(scene, args):
    """The scene's positions after args.prepare units of time of LangevinMiddleIntegrator at
    dt = PREPARE_DT: every run starts from them, so that a large dt is judged on an
    equilibrium fluid, not on the overlaps of the random start."""
    if args.prepare <= 0:
        return scene.positions
    integrator = openmm.LangevinMiddleIntegrator(KT_TEMPERATURE, FRICTION, PREPARE_DT)
    integrator.setRandomNumberSeed(args.seed)
    context = openmm.Context(scene.system, integrator, *_platform(args))
    context.setPositions(scene.positions)
    context.setVelocitiesToTemperature(KT_TEMPERATURE, args.seed)
    integrator.step(round(args.prepare / PREPARE_DT))
    return context.getState(getPositions=True).getPositions()


def _start(scene, start, factory, dt, args):
    """(integrator, Context) at the start positions, velocities at kT = 1 with no net momentum."""
    integrator = factory(dt)
    if hasattr(integrator, "setRandomNumberSeed"):
        integrator.setRandomNumberSeed(args.seed)
    if hasattr(integrator, "setInstabilityThreshold"):  # ours, not OpenMM's
        integrator.setInstabilityThreshold(args.instability_threshold)
    context = openmm.Context(scene.system, integrator, *_platform(args))
    context.setPositions(start)
    context.setVelocitiesToTemperature(KT_TEMPERATURE, args.seed)
    v = context.getState(getVelocities=True).getVelocities(asNumpy=True)._value
    context.setVelocities(v - v.mean(axis=0))  # no net momentum (DPD conserves it)
    return integrator, context


def _sample(integrator, context, sampler, dt, args):
    """Equilibrates, then steps and samples; returns (CPU, wall) seconds spent in the steps."""
    stride, samples, frame_every = schedule(dt, args)
    integrator.step(round(args.equilibrate / dt))
    sampler.frame(context.getState(getPositions=True).getPositions(asNumpy=True)._value)  # the MSD's origin
    cpu = wall = 0.0
    for k in range(samples):
        c0, w0 = time.process_time(), time.perf_counter()
        integrator.step(stride)
        cpu += time.process_time() - c0
        wall += time.perf_counter() - w0
        state = context.getState(getPositions=True, getVelocities=True)
        pos = state.getPositions(asNumpy=True)._value
        kT = sampler.sample(pos, state.getVelocities(asNumpy=True)._value)
        if not math.isfinite(kT) or kT > 10:
            raise openmm.OpenMMException(f"kinetic temperature {kT:.3g} at step {(k + 1) * stride}")
        if (k + 1) % frame_every == 0:
            sampler.frame(pos)
    return cpu, wall


def _cpu_seconds(integrator, steps):
    start = time.process_time()
    integrator.step(steps)
    return time.process_time() - start


def cost_against_langevin(scene, integrator, context, dt, steps, args):
    """The cost of a step of `integrator` as a ratio to a LangevinMiddleIntegrator step on the
    same System at the same dt, from the same state: `steps` steps of each in turn,
    args.cost_repeats times; the median of the per-repeat ratios of CPU seconds, with its
    standard error from their spread (machine noise slower than a repeat cancels in a ratio).
    Returns the cost columns; none where Langevin fails (it may blow up at a large dt)."""
    langevin = openmm.LangevinMiddleIntegrator(KT_TEMPERATURE, FRICTION, dt)
    langevin.setRandomNumberSeed(args.seed)
    reference = openmm.Context(scene.system, langevin, *_platform(args))
    reference.setState(context.getState(getPositions=True, getVelocities=True))
    ratios, base = [], []
    for k in range(args.cost_repeats + 1):
        mine = _cpu_seconds(integrator, steps)  # an instability here stops the run
        try:
            theirs = _cpu_seconds(langevin, steps)
        except openmm.OpenMMException:
            return {}  # Langevin itself fails at this dt: no cost
        if k > 0:  # the first round warms Langevin's new Context up (its neighbour list)
            ratios.append(mine / theirs)
            base.append(theirs)
    ratio, error = median_with_error(ratios)
    return dict(cost_ratio=ratio, cost_ratio_err=error, cost_per_time=ratio / dt, cost_per_time_err=error / dt,
                langevin_cpu_s_per_time=float(np.median(base)) / (steps * dt))


def run_one(scene, start, name, factory, dt, args):
    """One integrator at one dt from the start positions: (a dict with the COLUMNS, g(r) or None)."""
    row = {c: float("nan") for c in COLUMNS}
    row.update(scene=scene.name, integrator=name, dt=dt, status="ok", reason="", steps=0, note="")
    try:
        integrator, context = _start(scene, start, factory, dt, args)
    except openmm.OpenMMException as error:
        row.update(status="invalid", note=str(error).splitlines()[0][:160])
        return row, None
    sampler = Sampler(scene, args.a)
    stride, samples, frame_every = schedule(dt, args)
    try:
        cpu, wall = _sample(integrator, context, sampler, dt, args)
        # the sheared run starts here, not after the timed blocks, whose length follows the machine's speed
        final = context.getState(getPositions=True, getVelocities=True, enforcePeriodicBox=True)
        # blocks of ~args.cost_block seconds: many of the scheduler's time slices, so a block
        # is not made slow by one slice given to another process
        block = max(1, round(args.cost_block * samples * stride / max(cpu, 1e-9)))
        row.update(cost_against_langevin(scene, integrator, context, dt, block, args))
    except openmm.OpenMMException as error:
        message = str(error).splitlines()[0][:160]
        mark_unstable(row, failure_reason(message), message)
        row["steps"] = len(sampler.kT) * stride
        return row, None
    simulated = samples * stride * dt
    row.update(steps=samples * stride, cpu_s_per_time=cpu / simulated, wall_s_per_time=wall / simulated)
    g = sampler.summarise(row, stride * dt, frame_every * stride * dt, args.gr_frames)
    judge(row, scene.name)
    if row["status"] == "ok" and args.nemd_time > 0:
        shear_viscosity(row, scene.system, final, factory, dt, args)
        row["Sc"], row["Sc_err"] = dynamics.schmidt_number(row["eta"], row["eta_err"], row["D"], row["D_err"],
                                                           sampler.mass_density())
    return row, g


def shear_viscosity(row, system, state, factory, dt, args):
    """eta and its error in row from a run sheared at args.nemd_rate from `state`, where the sampled
    run ended.  An integrator without shear or a pressure tensor gets none; a sheared run that stops
    makes the run unstable (`shear`)."""
    try:
        integrator = dynamics.sheared_integrator(factory, dt, args.nemd_rate, args.seed, args.instability_threshold)
    except (AttributeError, openmm.OpenMMException):
        return
    try:
        sheared = dynamics.sheared_context(system, state, integrator, args.nemd_rate, _platform(args))
        row["eta"], row["eta_err"] = dynamics.nemd_viscosity(sheared, integrator, args.nemd_rate, args.equilibrate,
                                                             args.nemd_time, dt)
    except openmm.OpenMMException as error:
        message = str(error).splitlines()[0][:140]
        mark_unstable(row, "shear", f"sheared at rate {args.nemd_rate:g}: {message}")


def _deviations(rows, names, g_of):
    """g(r) of each stable run against its integrator's smallest-dt stable run."""
    for name in names:
        ok = [row for row in rows if row["integrator"] == name and row["status"] == "ok"
              and (name, row["dt"]) in g_of]
        if not ok:
            continue
        ref = min(ok, key=lambda row: row["dt"])
        for row in ok:
            g, g_ref = g_of[(name, row["dt"])], g_of[(name, ref["dt"])]
            row["g_dev_ref"] = float(np.sqrt(np.mean((g - g_ref) ** 2)))


def judge_dynamics(rows):
    """Each run's D, eta, Sc and eta_T against the dt -> 0 limits of the rows (dynamics.limits),
    and whether it is usable; returns the limits."""
    fitted = dynamics.limits(rows)
    dynamics.relative_to_limits(rows, fitted)
    for row in rows:
        row["usable"] = int(dynamics.usable(row))
    return fitted


def _write_csvs(out, rows, r, g_of):
    with open(os.path.join(out, "results.csv"), "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=COLUMNS)
        writer.writeheader()
        writer.writerows(rows)
    with open(os.path.join(out, "gr.csv"), "w", newline="") as f:
        writer = csv.writer(f)
        keys = sorted(g_of)
        writer.writerow(["r"] + [f"{name} dt={dt:g}" for name, dt in keys])
        for k, rk in enumerate(r):
            writer.writerow([f"{rk:.4f}"] + [f"{g_of[key][k]:.5f}" for key in keys])


def compare(args):
    began = time.perf_counter()
    os.makedirs(args.out, exist_ok=True)
    scene = build_scene(args.scene, num_particles=args.particles, **({"a": args.a} if args.scene == "soft" else {}))
    factories = integrators(args.scene)
    names = args.integrators or [name for name in factories if name != "Langevin"] + ["Langevin"]
    unknown = [x for x in names if x not in factories]
    if unknown:
        raise SystemExit(f"unknown integrators {unknown}; available: {', '.join(factories)}")
    runs = [(name, dt) for name in names for dt in sorted(args.dts)]
    try:
        from tqdm import tqdm
        progress = tqdm(runs, desc=f"compare {args.scene}", unit="run", disable=args.quiet)
    except ImportError:
        progress = runs
    start = equilibrated_positions(scene, args)
    rows, g_of = [], {}
    for name, dt in progress:
        row, g = run_one(scene, start, name, factories[name], dt, args)
        rows.append(row)
        if g is not None:
            g_of[(name, dt)] = g
    if scene.name == "soft":
        judge_overlaps(rows)
    _deviations(rows, names, g_of)
    judge_dynamics(rows)
    r = g_r_centres(scene.system)
    _write_csvs(args.out, rows, r, g_of)
    write_report(args, rows, r, g_of, time.perf_counter() - began)
    return rows


def redraw(args):
    """The charts and report.md of the finished run in args.out, from its results.csv and gr.csv,
    without running anything: the scene and the time steps come from results.csv, the other
    settings the report describes from args, which must be the run's (its sampled steps are
    checked against --time and --sample-every); the run's duration is kept from the report
    being replaced.  Returns the rows."""
    rows = read_rows(os.path.join(args.out, "results.csv"))
    for row in rows:  # a run made before a column was measured
        for column in COLUMNS:
            row.setdefault(column, float("nan"))
    args.scene = rows[0]["scene"]
    args.dts = sorted({row["dt"] for row in rows})
    for row in rows:
        stride, samples, _ = schedule(row["dt"], args)
        if row["status"] == "ok" and row["steps"] != samples * stride:
            raise SystemExit(f"{row['integrator']} at dt {row['dt']:g} sampled {row['steps']:g} steps, not the "
                             f"{samples * stride} of --time {args.time:g} and --sample-every {args.sample_every:g}: "
                             "give the options the run was made with")
    r, g_of = read_gr(os.path.join(args.out, "gr.csv"))
    write_report(args, rows, r, g_of, _duration(os.path.join(args.out, "report.md")))
    return rows


def _duration(path):
    """The wall seconds a report says its run took (None without one): a redrawn report keeps it."""
    if not os.path.exists(path):
        return None
    with open(path) as f:
        found = re.search(r"The whole run took (\d+) s", f.read())
    return float(found.group(1)) if found else None


# How long a run with the defaults takes, for --help (docs/results/README.md: about 10 minutes for
# scene soft on a 2-core machine, the sheared runs that give eta included).
DURATION = ("With the defaults (scene soft, N 2000, 100 time units per run and 100 more sheared for eta, every "
            "integrator at 6 time steps: 72 runs) a run takes about 10 minutes on 2 cores; each integrator's "
            "time grows as --particles times --time (and --nemd-time) times the sum of 1/dt over --dts. "
            "--quick takes seconds.")

# --quick (options.add_quick)
QUICK = dict(particles=500, time=3.0, equilibrate=0.5, prepare=1.0, frame_every=0.5, gr_frames=4, cost_block=0.01,
             cost_repeats=3, dts=[0.02, 0.06, 0.15], nemd_time=2.0)


def _parser():
    parser = options.parser("compare", __doc__.split("\n\n")[0], DURATION)  # the first paragraph, whole
    add = parser.add_argument
    add("--scene", default="soft", choices=SCENES, help="the System every integrator runs")
    add("--integrators", nargs="+", help="names from openmmdpd.catalog (default: all available on the scene)")
    add("--dts", type=float, nargs="+", default=[0.02, 0.03, 0.04, 0.06, 0.1, 0.15],
        help="time steps (ps = reduced time) each integrator runs at")
    add("--particles", type=int, default=2000, help="N")
    add("--a", type=float, default=25.0, help="soft repulsion (scene soft)")
    add("--time", type=float, default=100.0, help="simulated time sampled per run (reduced units)")
    add("--equilibrate", type=float, default=2.0, help="time each run equilibrates before sampling")
    add("--prepare", type=float, default=5.0,
        help="time of Langevin at dt 0.005 that equilibrates the start of every run (0: the random start)")
    add("--sample-every", type=float, default=0.1, help="time between samples of kT (at least one step)")
    add("--frame-every", type=float, default=2.0, help="time between frames (positions, configurational kT)")
    add("--gr-frames", type=int, default=8, help="frames, spread over the run, whose g(r) is measured")
    add("--nemd-rate", type=float, default=0.5, help="shear rate of the NEMD run that gives eta (1/ps)")
    add("--nemd-time", type=float, default=100.0,
        help="time the NEMD run samples after --equilibrate (0: no eta); stable runs of integrators with shear only")
    add("--reference-diffusion", default=os.path.join("docs", "results", "dynamics-limit", "diffusion", "results.csv"),
        help="results.csv of a long run at a small dt whose D the dt -> 0 limit is checked against (if it exists)")
    add("--reference-viscosity", default=os.path.join("docs", "results", "dynamics-limit", "viscosity", "nemd.csv"),
        help="nemd.csv of the viscosity tool's long NEMD run whose eta at --nemd-rate the limit is checked against "
             "(if it exists)")
    add("--cost-block", type=float, default=0.1, help="CPU seconds per timed block of the cost ratio to Langevin")
    add("--cost-repeats", type=int, default=7, help="alternating timed blocks (integrator, Langevin)")
    options.add_quick(parser, QUICK)
    add("--platform", default="CPU", help="OpenMM platform")
    add("--threads", type=int, default=os.cpu_count() or 1, help="CPU platform threads, one per core here")
    add("--seed", type=int, default=2024, help="seed of the start and of every integrator")
    add("--instability-threshold", type=float, default=INSTABILITY_THRESHOLD,
        help="stop a run when a particle's kinetic energy passes this many kT (0: off)")
    add("--out", default=None, help="output folder (default results/compare-SCENE)")
    add("--quiet", action="store_true", help="no progress bar")
    add("--redraw", action="store_true",
        help="no runs: redraw the charts and rewrite report.md of the run in --out from its results.csv and "
             "gr.csv (seconds); the scene and time steps are read from results.csv, the other options must be "
             "the run's, as the report states them")
    return parser


def main(argv=None):
    use_file_backend()
    args = options.parse_args(_parser(), argv, QUICK)
    args.out = args.out or os.path.join("results", f"compare-{args.scene}")
    if args.redraw:
        redraw(args)
        print(f"charts and report in {args.out}/ redrawn from its results.csv and gr.csv")
        return 0
    start = time.perf_counter()
    rows = compare(args)
    stable = sum(row["status"] == "ok" for row in rows)
    print(f"{len(rows)} runs ({stable} stable) in {time.perf_counter() - start:.0f} s; "
          f"results, charts and report in {args.out}/")
    return 0


if __name__ == "__main__":
    sys.exit(main())
