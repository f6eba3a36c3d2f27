"""The main job: every integrator on a scene over a sweep of time steps, measured for
accuracy and for cost in the same run, with charts, the CSV behind them and a report.

    /usr/bin/python3 -m openmmdpd.compare [--scene soft] [--out results/compare-soft]

Per run: kinetic <kT> (3N - 3 dof) and its standard error, configurational temperature
(scenes with the soft repulsion), g(r) and its deviation from the same integrator at the
smallest dt (and from 1 on `ideal`), coordination number Nc, tracer diffusion D from the
MSD, chain <kT> and Rg (polymer), and CPU seconds per unit of simulated time.  A run that
blows up is recorded as unstable, not raised; so is one in which a particle's kinetic energy
passes the instability threshold (40 kT by default: a transient blow-up that would otherwise
recover and go into the averages).

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

from .analysis import block_average
from .catalog import CUTOFF, INSTABILITY_THRESHOLD, integrators
from .scenes import SCENES, build_scene
from .units import KT_TEMPERATURE

G_R_MAX, G_BINS = 2.0, 80
COLUMNS = ["scene", "integrator", "dt", "status", "steps", "kT", "kT_err", "kT_error", "kT_conf",
           "g_dev_ref", "g_dev_ideal", "Nc", "D", "D_ratio", "chain_kT", "Rg", "cpu_s_per_time",
           "wall_s_per_time", "note"]


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
    edges = np.linspace(0, r_max, bins + 1)
    shell = 4 / 3 * np.pi * (edges[1:] ** 3 - edges[:-1] ** 3)
    ideal = 0.5 * n * (n - 1) / length ** 3 * shell * frames
    return 0.5 * (edges[1:] + edges[:-1]), counts / ideal


def coordination_number(r, g, density):
    """Nc = 4 pi rho int_0^r1 g r^2 dr, r1 = the first minimum after the main peak.

    The first minimum of a soft fluid's g(r) is shallow and broad: it is located on g
    smoothed over 9 bins (0.2 rc), within 0.8 rc after the peak, refined by a parabola
    through the three bins around it, and the integral runs to r1 itself (not to a bin
    edge), so Nc does not jump by whole shells from one run to the next.
    """
    smooth = np.convolve(g, np.ones(9) / 9, mode="same")
    peak = int(np.argmax(smooth))
    if smooth[peak] < 1.02:
        return float("nan")  # no structure (ideal gas): no shell to count
    dr = r[1] - r[0]
    window = np.arange(peak + 1, min(len(g) - 5, peak + int(0.8 / dr)))
    if len(window) == 0:
        return float("nan")
    k = int(window[np.argmin(smooth[window])])
    y0, y1, y2 = smooth[k - 1], smooth[k], smooth[k + 1]
    curvature = y0 - 2 * y1 + y2
    r1 = r[k] + (0.5 * dr * (y0 - y2) / curvature if curvature > 0 else 0.0)
    integrand = g * r ** 2
    edges = np.concatenate([[0.0], 0.5 * (r[1:] + r[:-1])])  # lower edge of each bin
    inside = edges + dr <= r1
    partial = np.argmax(~inside)  # the bin r1 falls in
    total = integrand[inside].sum() * dr + integrand[partial] * (r1 - edges[partial])
    return float(4 * np.pi * density * total)


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


def run_one(scene, name, factory, dt, args):
    """One integrator at one dt: a dict with the COLUMNS."""
    system = scene.system
    n = system.getNumParticles()
    length = _box_length(system)
    row = {c: float("nan") for c in COLUMNS}
    row.update(scene=scene.name, integrator=name, dt=dt, status="ok", steps=0, note="")
    platform = openmm.Platform.getPlatformByName(args.platform)
    properties = {"Threads": str(args.threads)} if args.platform == "CPU" else {}
    try:
        integrator = factory(dt)
        if hasattr(integrator, "setRandomNumberSeed"):
            integrator.setRandomNumberSeed(args.seed)
        if hasattr(integrator, "setInstabilityThreshold"):  # ours, not OpenMM's
            integrator.setInstabilityThreshold(args.instability_threshold)
        context = openmm.Context(system, integrator, platform, properties)
    except openmm.OpenMMException as error:
        row.update(status="invalid", note=str(error).splitlines()[0][:160])
        return row, None
    context.setPositions(scene.positions)
    context.setVelocitiesToTemperature(KT_TEMPERATURE, args.seed)
    v = context.getState(getVelocities=True).getVelocities(asNumpy=True)._value
    context.setVelocities(v - v.mean(axis=0))  # no net momentum (DPD conserves it)
    dof = 3 * n - 3
    chain = np.array(scene.chain_particles[0]) if scene.chain_particles else None
    kT, chain_kT, rg, conf_num, conf_den = [], [], [], 0.0, 0.0
    counts = np.zeros(G_BINS)
    frames = 0
    msd_times, msd = [], []
    stride = args.stride
    cpu = wall = 0.0
    try:
        integrator.step(args.equilibrate)
        start = context.getState(getPositions=True).getPositions(asNumpy=True)._value
        for k in range(args.steps // stride):
            c0, w0 = time.process_time(), time.perf_counter()
            integrator.step(stride)
            cpu += time.process_time() - c0
            wall += time.perf_counter() - w0
            state = context.getState(getPositions=True, getVelocities=True)
            pos = state.getPositions(asNumpy=True)._value
            vel = state.getVelocities(asNumpy=True)._value
            v2 = (vel * vel).sum(axis=1)  # unit masses
            kT.append(v2.sum() / dof)
            if not math.isfinite(kT[-1]) or kT[-1] > 10:
                raise openmm.OpenMMException(f"kinetic temperature {kT[-1]:.3g} at step {(k + 1) * stride}")
            if chain is not None:
                chain_kT.append(v2[chain].sum() / (3 * len(chain)))
                centred = pos[chain] - pos[chain].mean(axis=0)
                rg.append(math.sqrt((centred * centred).sum(axis=1).mean()))
            if (k + 1) % args.frame_every == 0:
                counts += pair_histogram(pos, length)
                frames += 1
                if scene.name != "ideal" and chain is None:
                    num, den = soft_repulsion_laplacian(pos, length, args.a)
                    conf_num += num
                    conf_den += den
                msd_times.append((k + 1) * stride * dt)
                disp = pos - start
                msd.append((disp * disp).sum(axis=1).mean())
    except openmm.OpenMMException as error:
        row.update(status="unstable", steps=len(kT) * stride, note=str(error).splitlines()[0][:160])
        return row, None
    simulated = args.steps * dt
    mean, err = block_average(np.array(kT), nblocks=max(2, min(10, len(kT))))
    r, g = radial_distribution(counts, max(frames, 1), n, length)
    row.update(steps=args.steps, kT=mean, kT_err=err, kT_error=abs(mean - 1),
               kT_conf=conf_num / conf_den if conf_den > 0 else float("nan"),
               g_dev_ideal=float(np.sqrt(np.mean((g[r > 0.1] - 1) ** 2))) if scene.name == "ideal" else float("nan"),
               Nc=coordination_number(r, g, n / length ** 3) if frames else float("nan"),
               D=diffusion(np.array(msd_times), np.array(msd)),
               chain_kT=float(np.mean(chain_kT)) if chain_kT else float("nan"),
               Rg=float(np.mean(rg)) if rg else float("nan"),
               cpu_s_per_time=cpu / simulated, wall_s_per_time=wall / simulated)
    if mean > 1.5 or mean < 0.5:
        row.update(status="unstable", note=f"<kT> = {mean:.3g}")
    elif math.isfinite(row["kT_conf"]) and abs(row["kT_conf"] - 1) > 0.1:
        # Stable and kinetically fine, but the configurations are not at kT = 1.
        row.update(note=f"configurational kT = {row['kT_conf']:.3g}")
    return row, g


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
    # Deviations from each integrator's own smallest-dt g(r) and D.
    for name in names:
        ok = [row for row in rows if row["integrator"] == name and row["status"] == "ok"]
        if not ok:
            continue
        ref = min(ok, key=lambda row: row["dt"])
        for row in ok:
            g, g_ref = g_of[(name, row["dt"])], g_of[(name, ref["dt"])]
            row["g_dev_ref"] = float(np.sqrt(np.mean((g - g_ref) ** 2)))
            row["D_ratio"] = row["D"] / ref["D"] if ref["D"] else float("nan")
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
