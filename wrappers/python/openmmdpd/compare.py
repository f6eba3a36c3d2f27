"""The main job: every integrator on a scene over a sweep of time steps, measured for
accuracy and for cost in the same run, with charts, the CSV behind them and a report.

    /usr/bin/python3 -m openmmdpd.compare [--scene soft] [--out results/compare-soft]

Per run: kinetic <kT> (3N - 3 dof), configurational temperature (scene soft), chain <kT>
and Rg (polymer), each with its standard error from the statistical inefficiency (pymbar);
g(r) and its deviation from the same integrator at the smallest dt (and from 1 on `ideal`);
the coordination number Nc to the first minimum r1 (both with errors from blocks of frames)
and at the fixed radii 1.0 and 1.16; tracer diffusion D from the MSD; and CPU seconds per
unit of simulated time.  A run is stable only if it does not blow up, does not pass the
instability threshold (40 kT by default: a transient blow-up that would otherwise recover
and go into the averages), has <kT> in [0.5, 1.5], and on scene soft has a configurational
kT within 10 % of 1 and no overlapping particles (g(r < 0.2) more than 0.2 above that of
the smallest dt); an unstable run is recorded with its reason, not raised.

Observables are accumulated in the loop from States (positions, velocities) rather than
written to a trajectory for MDTraj/MDAnalysis: the runs are short, the analysis is a few
pair histograms (scipy's periodic cKDTree), and no files are needed in between.
"""
import argparse
import csv
import math
import os
import sys
import time

import numpy as np
import openmm
from openmm import unit
from scipy.spatial import cKDTree

from .analysis import ratio_with_error, standard_error
from .catalog import CUTOFF, INSTABILITY_THRESHOLD, integrators
from .scenes import SCENES, build_scene
from .units import KT_TEMPERATURE

G_R_MAX, G_BINS = 2.0, 80
FIXED_RADII = (1.0, 1.16)  # Nc at these radii: r1 sits on a minimum too flat to integrate to
R1_BLOCKS = 5              # blocks of g(r) frames whose spread gives the errors of r1 and Nc(r1)
CONF_KT_TOLERANCE = 0.1    # a stable run's configurational kT is within 10 % of 1 (soft scene)
CORE_RADIUS = 0.2          # g(r < 0.2 rc): pairs overlapping by 80 % (8 kT of repulsion at a = 25)
OVERLAP_EXCESS = 0.2       # how far above the smallest-dt g(r < 0.2 rc) means overlapping particles
COLUMNS = ["scene", "integrator", "dt", "status", "reason", "steps", "kT", "kT_err", "kT_error", "kT_conf",
           "kT_conf_err", "g_core", "g_dev_ref", "g_dev_ideal", "Nc", "Nc_err", "r1", "r1_err", "Nc_1.0",
           "Nc_1.0_err", "Nc_1.16", "Nc_1.16_err", "D", "D_ratio", "chain_kT", "chain_kT_err", "Rg", "Rg_err",
           "cpu_s_per_time", "wall_s_per_time", "note"]


# --- observables ------------------------------------------------------------------------------

def _box_length(system):
    return system.getDefaultPeriodicBoxVectors()[0][0].value_in_unit(unit.nanometer)


def pair_histogram(positions, length, r_max=G_R_MAX, bins=G_BINS):
    """Counts of pair distances in [0, r_max) of a cubic periodic box."""
    tree = cKDTree(np.mod(positions, length), boxsize=length)
    pairs = tree.query_pairs(r_max, output_type="ndarray")
    d = positions[pairs[:, 0]] - positions[pairs[:, 1]]
    d -= length * np.round(d / length)
    return np.histogram(np.sqrt((d * d).sum(axis=1)), bins=bins, range=(0, r_max))[0]


def radial_distribution(counts, frames, n, length, r_max=G_R_MAX, bins=G_BINS):
    """(bin centres, g) from pair counts summed over frames; counts may also be one row per frame."""
    edges = np.linspace(0, r_max, bins + 1)
    shell = 4 / 3 * np.pi * (edges[1:] ** 3 - edges[:-1] ** 3)
    ideal = 0.5 * n * (n - 1) / length ** 3 * shell * frames
    return 0.5 * (edges[1:] + edges[:-1]), counts / ideal


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


def shell_structure(frame_counts, n, length):
    """(r, g, {Nc, Nc_err, r1, r1_err, Nc_1.0, Nc_1.0_err, ...}) from one pair histogram per frame.

    r1 and Nc(r1) get their errors from the spread of R1_BLOCKS consecutive blocks of frames;
    Nc at the fixed radii from its per-frame series (statistical inefficiency).
    """
    frame_counts = np.asarray(frame_counts, dtype=float)
    density = n / length ** 3
    r, g = radial_distribution(frame_counts.sum(axis=0), len(frame_counts), n, length)
    r1 = first_minimum(r, g)
    blocks = np.array_split(frame_counts, min(R1_BLOCKS, len(frame_counts)))
    block_g = [radial_distribution(b.sum(axis=0), len(b), n, length)[1] for b in blocks]
    block_r1 = [first_minimum(r, gb) for gb in block_g]
    shells = dict(r1=r1, r1_err=_spread(block_r1), Nc=float(coordination_at(r, g, r1, density)),
                  Nc_err=_spread([coordination_at(r, gb, x, density) for gb, x in zip(block_g, block_r1)]))
    per_frame = radial_distribution(frame_counts, 1, n, length)[1]
    for radius in FIXED_RADII:
        series = coordination_at(r, per_frame, radius, density)
        shells[f"Nc_{radius}"], shells[f"Nc_{radius}_err"] = float(series.mean()), standard_error(series)
    return r, g, shells


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
    """D = slope / 6 of the MSD over the second half of the lags."""
    half = len(times) // 2
    if len(times) - half < 2:
        return float("nan")
    slope = np.polyfit(times[half:], msd[half:], 1)[0]
    return float(slope / 6)


# --- stability --------------------------------------------------------------------------------

def mark_unstable(row, reason, note):
    row.update(status="unstable", reason=reason, note=note)


def failure_reason(message):
    """Why a run that stopped with this message is unstable: the instability sentinel, or a
    blow-up (a non-finite value, a particle jumping cutoffs, a sampled kT above 10)."""
    return "sentinel" if "instability threshold" in message else "blow-up"


def judge(row, soft):
    """Marks a completed run unstable if its <kT> is outside [0.5, 1.5] or, on a scene with
    the soft repulsion (soft), its configurational kT is more than 10 % from 1."""
    if not 0.5 <= row["kT"] <= 1.5:
        mark_unstable(row, "kT", f"<kT> = {row['kT']:.3g}, outside [0.5, 1.5]")
    elif soft and abs(row["kT_conf"] - 1) > CONF_KT_TOLERANCE:
        mark_unstable(row, "kT_conf", f"configurational kT = {row['kT_conf']:.3g}, more than 10 % from 1")


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
    """One run's time series, taken every `stride` steps, and its frames (g(r) histograms,
    configurational temperature, MSD) every `frame_every` samples."""

    def __init__(self, scene, a):
        self.n, self.length = scene.system.getNumParticles(), _box_length(scene.system)
        self.ideal = scene.name == "ideal"
        self.soft = scene.name == "soft"  # the one scene whose whole potential is the soft repulsion
        self.a = a
        self.chain = np.array(scene.chain_particles[0]) if scene.chain_particles else None
        self.kT, self.chain_kT, self.rg, self.force2, self.laplacian, self.counts = [], [], [], [], [], []
        self.msd_times, self.msd, self.origin = [], [], None

    def sample(self, pos, vel):
        """Records one sample; returns its kinetic kT."""
        v2 = (vel * vel).sum(axis=1)  # unit masses
        self.kT.append(v2.sum() / (3 * self.n - 3))
        if self.chain is not None:
            self.chain_kT.append(v2[self.chain].sum() / (3 * len(self.chain)))
            centred = pos[self.chain] - pos[self.chain].mean(axis=0)
            self.rg.append(math.sqrt((centred * centred).sum(axis=1).mean()))
        return self.kT[-1]

    def frame(self, pos, time):
        self.counts.append(pair_histogram(pos, self.length))
        if self.soft:
            f2, lap = soft_repulsion_laplacian(pos, self.length, self.a)
            self.force2.append(f2)
            self.laplacian.append(lap)
        disp = pos - self.origin
        self.msd_times.append(time)
        self.msd.append((disp * disp).sum(axis=1).mean())

    def summarise(self, row):
        """Puts the observables and their standard errors in row; returns g(r) (None without frames)."""
        kT = np.array(self.kT)
        row.update(kT=kT.mean(), kT_err=standard_error(kT), kT_error=abs(kT.mean() - 1),
                   D=diffusion(np.array(self.msd_times), np.array(self.msd)))
        if self.force2:
            row["kT_conf"], row["kT_conf_err"] = ratio_with_error(self.force2, self.laplacian)
        if self.chain_kT:
            row.update(chain_kT=float(np.mean(self.chain_kT)), chain_kT_err=standard_error(self.chain_kT),
                       Rg=float(np.mean(self.rg)), Rg_err=standard_error(self.rg))
        if not self.counts:
            return None
        r, g, shells = shell_structure(self.counts, self.n, self.length)
        row.update(shells, g_core=float(g[r < CORE_RADIUS].mean()))
        if self.ideal:
            row["g_dev_ideal"] = float(np.sqrt(np.mean((g[r > 0.1] - 1) ** 2)))
        return g


def _start(scene, factory, dt, args):
    """(integrator, Context) at the scene's positions, velocities at kT = 1 with no net momentum."""
    platform = openmm.Platform.getPlatformByName(args.platform)
    properties = {"Threads": str(args.threads)} if args.platform == "CPU" else {}
    integrator = factory(dt)
    if hasattr(integrator, "setRandomNumberSeed"):
        integrator.setRandomNumberSeed(args.seed)
    if hasattr(integrator, "setInstabilityThreshold"):  # ours, not OpenMM's
        integrator.setInstabilityThreshold(args.instability_threshold)
    context = openmm.Context(scene.system, integrator, platform, properties)
    context.setPositions(scene.positions)
    context.setVelocitiesToTemperature(KT_TEMPERATURE, args.seed)
    v = context.getState(getVelocities=True).getVelocities(asNumpy=True)._value
    context.setVelocities(v - v.mean(axis=0))  # no net momentum (DPD conserves it)
    return integrator, context


def _sample(integrator, context, sampler, dt, args):
    """Equilibrates, then steps and samples; returns (CPU, wall) seconds spent in the steps."""
    integrator.step(args.equilibrate)
    sampler.origin = context.getState(getPositions=True).getPositions(asNumpy=True)._value
    cpu = wall = 0.0
    for k in range(args.steps // args.stride):
        c0, w0 = time.process_time(), time.perf_counter()
        integrator.step(args.stride)
        cpu += time.process_time() - c0
        wall += time.perf_counter() - w0
        state = context.getState(getPositions=True, getVelocities=True)
        pos = state.getPositions(asNumpy=True)._value
        kT = sampler.sample(pos, state.getVelocities(asNumpy=True)._value)
        if not math.isfinite(kT) or kT > 10:
            raise openmm.OpenMMException(f"kinetic temperature {kT:.3g} at step {(k + 1) * args.stride}")
        if (k + 1) % args.frame_every == 0:
            sampler.frame(pos, (k + 1) * args.stride * dt)
    return cpu, wall


def run_one(scene, name, factory, dt, args):
    """One integrator at one dt: (a dict with the COLUMNS, g(r) or None)."""
    row = {c: float("nan") for c in COLUMNS}
    row.update(scene=scene.name, integrator=name, dt=dt, status="ok", reason="", steps=0, note="")
    try:
        integrator, context = _start(scene, factory, dt, args)
    except openmm.OpenMMException as error:
        row.update(status="invalid", note=str(error).splitlines()[0][:160])
        return row, None
    sampler = Sampler(scene, args.a)
    try:
        cpu, wall = _sample(integrator, context, sampler, dt, args)
    except openmm.OpenMMException as error:
        message = str(error).splitlines()[0][:160]
        mark_unstable(row, failure_reason(message), message)
        row["steps"] = len(sampler.kT) * args.stride
        return row, None
    simulated = args.steps * dt
    row.update(steps=args.steps, cpu_s_per_time=cpu / simulated, wall_s_per_time=wall / simulated)
    g = sampler.summarise(row)
    judge(row, sampler.soft)
    return row, g


def _deviations(rows, names, g_of):
    """g(r) and D of each stable run against its integrator's smallest-dt stable run."""
    for name in names:
        ok = [row for row in rows if row["integrator"] == name and row["status"] == "ok"
              and (name, row["dt"]) in g_of]
        if not ok:
            continue
        ref = min(ok, key=lambda row: row["dt"])
        for row in ok:
            g, g_ref = g_of[(name, row["dt"])], g_of[(name, ref["dt"])]
            row["g_dev_ref"] = float(np.sqrt(np.mean((g - g_ref) ** 2)))
            row["D_ratio"] = row["D"] / ref["D"] if ref["D"] else float("nan")


def compare(args):
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
    rows, g_of = [], {}
    for name, dt in progress:
        row, g = run_one(scene, name, factories[name], dt, args)
        rows.append(row)
        if g is not None:
            g_of[(name, dt)] = g
    if scene.name == "soft":
        judge_overlaps(rows)
    _deviations(rows, names, g_of)
    csv_path = os.path.join(args.out, "results.csv")
    with open(csv_path, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=COLUMNS)
        writer.writeheader()
        writer.writerows(rows)
    r = 0.5 * (np.linspace(0, G_R_MAX, G_BINS + 1)[1:] + np.linspace(0, G_R_MAX, G_BINS + 1)[:-1])
    with open(os.path.join(args.out, "gr.csv"), "w", newline="") as f:
        writer = csv.writer(f)
        keys = sorted(g_of)
        writer.writerow(["r"] + [f"{name} dt={dt:g}" for name, dt in keys])
        for k, rk in enumerate(r):
            writer.writerow([f"{rk:.4f}"] + [f"{g_of[key][k]:.5f}" for key in keys])
    from .report import write_report
    write_report(args, rows, r, g_of)
    return rows


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])  # the first paragraph, whole
    parser.add_argument("--scene", default="soft", choices=SCENES)
    parser.add_argument("--integrators", nargs="+", help="default: all available")
    parser.add_argument("--dts", type=float, nargs="+", default=[0.01, 0.02, 0.04, 0.06, 0.1, 0.15])
    parser.add_argument("--particles", type=int, default=2000)
    parser.add_argument("--a", type=float, default=25.0, help="soft repulsion (scene soft)")
    parser.add_argument("--steps", type=int, default=1000, help="sampled steps per run")
    parser.add_argument("--equilibrate", type=int, default=300, help="steps before sampling")
    parser.add_argument("--stride", type=int, default=10, help="steps between samples")
    parser.add_argument("--frame-every", type=int, default=5, help="samples between g(r)/MSD frames")
    parser.add_argument("--platform", default="CPU")
    parser.add_argument("--threads", type=int, default=os.cpu_count() or 1)
    parser.add_argument("--seed", type=int, default=2024)
    parser.add_argument("--instability-threshold", type=float, default=INSTABILITY_THRESHOLD,
                        help="stop a run when a particle's kinetic energy passes this many kT (0: off)")
    parser.add_argument("--out", default=None, help="output folder (default results/compare-SCENE)")
    parser.add_argument("--quiet", action="store_true", help="no progress bar")
    args = parser.parse_args(argv)
    args.out = args.out or os.path.join("results", f"compare-{args.scene}")
    start = time.perf_counter()
    rows = compare(args)
    stable = sum(row["status"] == "ok" for row in rows)
    print(f"{len(rows)} runs ({stable} stable) in {time.perf_counter() - start:.0f} s; "
          f"results, charts and report in {args.out}/")
    return 0


if __name__ == "__main__":
    sys.exit(main())
