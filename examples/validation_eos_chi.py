"""Two checks of the standard DPD fluid against Groot and Warren (1997): the equation of state
p(rho) at kT = 1, and the Flory-Huggins chi of a binary monomer mixture against Delta a from
demixing in a slab.  CPU platform, ShardlowIntegrator (S1; --integrator for another), CSVs and a Markdown report (report.md) into
docs/results/validation-eos-chi/.

    PYTHONPATH=build/python /usr/bin/python3 examples/validation_eos_chi.py [--quick] [--out DIR]

Equation of state: N particles of one type (repulsion a) in a cubic box at density rho; the
pressure is the virial pressure of the integrator's pressure tensor, trace/3 of its kinetic
plus conservative parts.  The thermostat's (dissipative + random) part is measured and
reported but left out: in equilibrium its mean vanishes (the pair velocities are uncorrelated
with the pair separations), so what it adds at finite dt is an error of the discretisation,
not part of the fluid's pressure, and it is the pressure of the fluid that Groot and Warren fit.
Errors: the tensor is averaged over blocks of BLOCK_STEPS steps, and the standard error of the
mean of those block means comes from pymbar's statistical inefficiency.

chi: A and B beads (a_AA = a_BB = 25, a_AB = 25 + Delta a) at rho = 3 in an elongated box,
started as two pure slabs.  Each frame is shifted so that the A slab's centre (the phase of the
first Fourier mode of the A density along z) sits at Lz/4; the minority fraction phi is read
in the central PLATEAU of each slab (both phases, by symmetry the same phi), and
chi = ln[(1 - phi)/phi] / (1 - 2 phi), Flory-Huggins for N_A = N_B = 1.  Errors: block
averages (10 and 4 blocks) and pymbar's statistical inefficiency of the per-frame plateau phi,
the largest of the three, propagated to chi.
"""
import argparse
import csv
import math
import os
import time

import numpy as np
import openmm
from openmm import unit

from openmmdpd import catalog, scenes
from openmmdpd.analysis import block_average, standard_error
from openmmdpd.pressure import pressure_tensor

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "..", "docs", "results", "validation-eos-chi")

# Groot and Warren (1997): p = rho kT + alpha a rho^2 for rho > 2, alpha = 0.101 +- 0.001;
# chi = (0.286 +- 0.002) Delta a at rho = 3 (the slope openmmdpd.flory_huggins uses).
ALPHA, ALPHA_ERR = 0.101, 0.001
SLOPE, SLOPE_ERR = 0.286, 0.002

# (a, rho, dt): a = 25 and 15 across the densities of the fit, a = 25 at rho 3 again at dt 0.01 to
# bound the dt error, and a rho = 75 kT (water's compressibility) at rho 2, 4 and 5, where Allen
# and Tildesley's published DPD example gives pressures to compare with too.
EOS_POINTS = [(25.0, 3.0, 0.02), (25.0, 3.0, 0.01), (25.0, 4.0, 0.02), (25.0, 5.0, 0.02),
              (15.0, 3.0, 0.02), (15.0, 5.0, 0.02), (37.5, 2.0, 0.02), (18.75, 4.0, 0.02)]
# (Delta a, dt): the sweep at dt 0.02, and Delta a 12 again at 0.04 to bound the dt error.  Delta a 8
# (chi ~ 2.3, just past the critical chi = 2 of monomers) is left out: its phases differ little,
# its interfaces are wide and it equilibrates slowly (a 600 ps trial at dt 0.04 from pure slabs
# was still rising), beyond this script's budget.
CHI_POINTS = [(10.0, 0.02), (12.0, 0.02), (14.0, 0.02), (16.0, 0.02), (12.0, 0.04)]
BLOCK_STEPS = 50          # steps per pressure-tensor block (1 ps at dt 0.02)
FRAME_INTERVAL = 0.5      # ps between composition profiles
BIN = 0.5                 # rc, the profile's bins along z
PLATEAU = 5.0             # rc, the width of each slab's bulk read for phi
QUICK = dict(particles=500, eos_time=4.0, eos_equilibrate=2.0, eos_points=["25:3:0.02"],
             chi_points=["12:0.04"], slab=[5.0, 5.0, 16.0], chi_time=10.0, chi_equilibrate=5.0, plateau=3.0)


def context_for(system, positions, dt, seed, threads, scheme):
    integrator = catalog.integrators()[scheme](dt)
    integrator.setRandomNumberSeed(seed)
    platform = openmm.Platform.getPlatformByName("CPU")
    context = openmm.Context(system, integrator, platform, {"Threads": str(threads)})
    context.setPositions(positions)
    context.setVelocitiesToTemperature(catalog.KT_TEMPERATURE, seed)
    return context, integrator


def measure_eos(a, rho, dt, particles, equilibrate, sample, seed, threads, scheme):
    """One state point: dict of p (kinetic + conservative), its parts, their errors, and kT."""
    scene = scenes.soft_scene(particles, density=rho, a=a, seed=seed)
    context, integrator = context_for(scene.system, scene.positions, dt, seed, threads, scheme)
    integrator.step(round(equilibrate / dt))
    integrator.setPressureTensorEnabled(True)
    blocks = []
    for _ in range(max(2, round(sample / dt / BLOCK_STEPS))):
        integrator.resetPressureTensor()
        integrator.step(BLOCK_STEPS)
        # trace/3 of each part: total, kinetic, conservative, thermostat
        blocks.append([pressure_tensor(integrator, part)[:3].mean() for part in range(4)])
    total, kinetic, conservative, thermostat = np.array(blocks).T
    virial = kinetic + conservative
    row = dict(a=a, rho=rho, dt=dt, integrator=scheme, N=particles, sampled_ps=len(blocks) * BLOCK_STEPS * dt)
    for name, series in (("p", virial), ("p_kinetic", kinetic), ("p_conservative", conservative),
                         ("p_thermostat", thermostat), ("p_with_thermostat", total)):
        row[name], row[name + "_err"] = float(series.mean()), standard_error(series)
    # kinetic pressure = rho kT: the kinetic temperature the run kept
    row["kT"], row["kT_err"] = row["p_kinetic"] / rho, row["p_kinetic_err"] / rho
    row["alpha"] = (row["p"] - rho) / (a * rho ** 2)
    row["alpha_err"] = row["p_err"] / (a * rho ** 2)
    row["p_gw"] = rho + ALPHA * a * rho ** 2
    row["p_gw_err"] = ALPHA_ERR * a * rho ** 2
    row["p_rel_diff"] = row["p"] / row["p_gw"] - 1
    return row


def flory_huggins_chi(phi):
    """chi of a symmetric monomer mixture (N_A = N_B = 1) whose coexisting phases hold a
    minority fraction phi, and d chi / d phi for the error."""
    chi = math.log((1 - phi) / phi) / (1 - 2 * phi)
    dchi = (-1 / (phi * (1 - phi)) + 2 * chi) / (1 - 2 * phi)
    return chi, dchi


def phi_of_chi(chi):
    """The coexisting minority fraction Flory-Huggins predicts for chi > 2 (bisection)."""
    lo, hi = 1e-12, 0.5 - 1e-9
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        # ln((1-phi)/phi) - chi (1 - 2 phi) is > 0 below the root, < 0 between it and 1/2
        if math.log((1 - mid) / mid) - chi * (1 - 2 * mid) > 0:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def slab_system(delta_a, box, rho, seed):
    lx, ly, lz = box
    n = int(round(rho * lx * ly * lz))
    rng = np.random.default_rng(seed)
    positions = rng.uniform(0, 1, size=(n, 3)) * np.array(box)
    # A where z < Lz/2, B above: two pure slabs, so that the minority has to dissolve into each
    # phase (approached from phi = 0; the halves of the sampling check it got there).
    types = (positions[:, 2] >= lz / 2).astype(int)
    system = openmm.System()
    for _ in range(n):
        system.addParticle(1.0)
    system.setDefaultPeriodicBoxVectors(openmm.Vec3(lx, 0, 0), openmm.Vec3(0, ly, 0), openmm.Vec3(0, 0, lz))
    table = [[25.0, 25.0 + delta_a], [25.0 + delta_a, 25.0]]
    system.addForce(scenes.soft_repulsion_force(n, table, types))
    return system, positions, types


def measure_chi(delta_a, box, rho, dt, equilibrate, sample, plateau, seed, threads, scheme):
    """One Delta a: (row, profile rows)."""
    system, positions, types = slab_system(delta_a, box, rho, seed)
    lz = box[2]
    context, integrator = context_for(system, positions, dt, seed, threads, scheme)
    integrator.step(round(equilibrate / dt))
    nbins = int(round(lz / BIN))
    edges = np.linspace(0, lz, nbins + 1)
    centres = 0.5 * (edges[1:] + edges[:-1])
    in_a = np.abs(centres - lz / 4) < plateau / 2       # bins of the A-rich plateau
    in_b = np.abs(centres - 3 * lz / 4) < plateau / 2   # and of the B-rich one
    is_a, is_b = types == 0, types == 1
    count_a, count_b, phis, kinetic = [], [], [], []
    every = max(1, round(FRAME_INTERVAL / dt))
    n = len(types)
    for _ in range(max(20, round(sample / FRAME_INTERVAL))):
        integrator.step(every)
        state = context.getState(getPositions=True, getEnergy=True)
        z = state.getPositions(asNumpy=True).value_in_unit(unit.nanometer)[:, 2]
        phase = np.angle(np.exp(2j * np.pi * z[is_a] / lz).sum())
        shifted = np.mod(z - phase * lz / (2 * np.pi) + lz / 4, lz)
        ha = np.histogram(shifted[is_a], edges)[0]
        hb = np.histogram(shifted[is_b], edges)[0]
        count_a.append(ha)
        count_b.append(hb)
        # minority fraction in each phase, then their mean (the mixture is symmetric)
        phi_in_a = hb[in_a].sum() / (ha[in_a].sum() + hb[in_a].sum())
        phi_in_b = ha[in_b].sum() / (ha[in_b].sum() + hb[in_b].sum())
        phis.append((phi_in_a, phi_in_b))
        kinetic.append(2 * state.getKineticEnergy().value_in_unit(unit.kilojoule_per_mole) / (3 * n - 3))
    phis = np.array(phis)
    phi_series = phis.mean(axis=1)
    # The plateaus' composition fluctuates slowly (exchange across the interfaces: hundreds of ps),
    # so 10 blocks can be too short to be independent; the error is the largest of the estimates
    # from 10 and 4 blocks and from pymbar's statistical inefficiency, each kept in the CSV.
    phi, phi_err10 = block_average(phi_series, 10)
    phi_err4 = block_average(phi_series, 4)[1]
    phi_pymbar_err = standard_error(phi_series)
    phi_err = max(phi_err10, phi_err4, phi_pymbar_err)
    half = len(phi_series) // 2
    chi, dchi = flory_huggins_chi(phi)
    chi_err = abs(dchi) * phi_err
    row = dict(delta_a=delta_a, a_AB=25.0 + delta_a, rho=rho, box=f"{box[0]:g}x{box[1]:g}x{box[2]:g}", N=n, dt=dt,
               integrator=scheme,
               sampled_ps=len(phi_series) * every * dt, phi=phi, phi_err=phi_err,
               phi_A_rich=float(phis[:, 0].mean()), phi_A_rich_err=block_average(phis[:, 0], 10)[1],
               phi_B_rich=float(phis[:, 1].mean()), phi_B_rich_err=block_average(phis[:, 1], 10)[1],
               phi_first_half=float(phi_series[:half].mean()), phi_second_half=float(phi_series[half:].mean()),
               phi_err_10_blocks=phi_err10, phi_err_4_blocks=phi_err4, phi_pymbar_err=phi_pymbar_err,
               chi=chi, chi_err=chi_err, chi_per_delta_a=chi / delta_a, chi_per_delta_a_err=chi_err / delta_a,
               chi_gw=SLOPE * delta_a, phi_gw=phi_of_chi(SLOPE * delta_a), kT=float(np.mean(kinetic)))
    count_a, count_b = np.array(count_a, dtype=float), np.array(count_b, dtype=float)
    fraction_b = count_b / np.maximum(count_a + count_b, 1)
    profile = []
    for k, zc in enumerate(centres):
        mean, err = block_average(fraction_b[:, k], 10)
        profile.append(dict(delta_a=delta_a, dt=dt, z=zc, phi_B=mean, phi_B_err=err,
                            density=(count_a[:, k] + count_b[:, k]).mean() / (box[0] * box[1] * BIN),
                            plateau="A-rich" if in_a[k] else "B-rich" if in_b[k] else ""))
    # the plateau series in 10 ps means, to look at its slow fluctuations again without a rerun
    frames = max(1, min(len(phis), round(10.0 / (every * dt))))
    series = [dict(delta_a=delta_a, dt=dt, t_ps=(k + frames) * every * dt,
                   phi_A_rich=float(phis[k:k + frames, 0].mean()), phi_B_rich=float(phis[k:k + frames, 1].mean()))
              for k in range(0, len(phis) - frames + 1, frames)]
    return row, profile, series


def write_csv(path, rows):
    with open(path, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        for row in rows:
            writer.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in row.items()})


def report(eos, chi, args, seconds):
    lines = ["# Equation of state and chi against Delta a: Groot and Warren (1997)", "",
             "Written by `examples/validation_eos_chi.py` "
             f"({'--quick' if args.quick else 'full run'}, {seconds[0]:.0f} s for the equation of state, "
             f"{seconds[1]:.0f} s for chi, {args.threads} CPU threads); "
             f"{args.integrator} (the catalog's, gamma 4.5), CPU platform, kT = 1, rc = 1.", ""]
    if eos:
        lines += ["## Equation of state", "",
                  f"N = {args.particles}; p = trace/3 of the kinetic + conservative pressure tensor, "
                  f"averaged over {BLOCK_STEPS}-step blocks after {args.eos_equilibrate:g} ps; ± the standard error "
                  "(statistical inefficiency of the block means, pymbar).  Published: "
                  f"p = rho kT + alpha a rho^2, alpha = {ALPHA} ± {ALPHA_ERR}, the fit of Groot and Warren (1997) "
                  "for rho > 2.", "",
                  "| a | rho | dt | ps | p measured | p (alpha = 0.101) | p / p_GW - 1 | (p - rho)/(a rho^2) "
                  "| alpha published | thermostat part | kinetic kT |",
                  "|---|---|---|---|---|---|---|---|---|---|---|"]
        for r in eos:
            lines.append(f"| {r['a']:g} | {r['rho']:g} | {r['dt']:g} | {r['sampled_ps']:.0f} | "
                         f"{r['p']:.4f} ± {r['p_err']:.4f} | {r['p_gw']:.2f} ± {r['p_gw_err']:.2f} | "
                         f"{100 * r['p_rel_diff']:+.2f} % | {r['alpha']:.5f} ± {r['alpha_err']:.5f} | "
                         f"{ALPHA} ± {ALPHA_ERR} | {r['p_thermostat']:+.4f} ± {r['p_thermostat_err']:.4f} | "
                         f"{r['kT']:.4f} ± {r['kT_err']:.4f} |")
        lines.append("")
    if chi:
        lines += ["## chi against Delta a", "",
                  f"rho = 3, a_AA = a_BB = 25; started as two pure slabs, "
                  f"{args.chi_equilibrate:g} ps to equilibrate; phi read in the central {args.plateau:g} rc "
                  "of each slab; ± the largest of the standard errors from 10 and 4 block averages and pymbar.  "
                  "Published: chi = "
                  f"({SLOPE} ± {SLOPE_ERR}) Delta a at rho = 3 (Groot and Warren 1997).", "",
                  "| Delta a | dt | box | ps | phi measured | phi (first, second half) | phi from chi = 0.286 Delta a "
                  "| chi measured | chi / Delta a | published | kinetic kT |",
                  "|---|---|---|---|---|---|---|---|---|---|---|"]
        for r in chi:
            lines.append(f"| {r['delta_a']:g} | {r['dt']:g} | {r['box']} | {r['sampled_ps']:.0f} | "
                         f"{r['phi']:.4f} ± {r['phi_err']:.4f} | {r['phi_first_half']:.4f}, "
                         f"{r['phi_second_half']:.4f} | {r['phi_gw']:.4f} | {r['chi']:.3f} ± {r['chi_err']:.3f} | "
                         f"{r['chi_per_delta_a']:.4f} ± {r['chi_per_delta_a_err']:.4f} | {SLOPE} ± {SLOPE_ERR} | "
                         f"{r['kT']:.4f} |")
        lines.append("")
    return "\n".join(lines)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", default=OUT, help="folder for eos.csv, chi.csv, profiles.csv, report.md")
    parser.add_argument("--parts", nargs="+", choices=["eos", "chi"], default=["eos", "chi"])
    parser.add_argument("--particles", type=int, default=3000, help="N of each equation-of-state run")
    parser.add_argument("--eos-points", nargs="+", default=[f"{a:g}:{r:g}:{dt:g}" for a, r, dt in EOS_POINTS],
                        help="a:rho:dt of each equation-of-state run")
    parser.add_argument("--eos-time", type=float, default=60.0, help="ps sampled per equation-of-state run")
    parser.add_argument("--eos-equilibrate", type=float, default=20.0)
    parser.add_argument("--chi-points", nargs="+", default=[f"{d:g}:{dt:g}" for d, dt in CHI_POINTS],
                        help="Delta a:dt of each mixture run")
    parser.add_argument("--slab", type=float, nargs=3, default=[8.0, 8.0, 24.0], help="box Lx Ly Lz of the mixture")
    parser.add_argument("--chi-time", type=float, default=2000.0, help="ps sampled per Delta a")
    parser.add_argument("--chi-equilibrate", type=float, default=500.0)
    parser.add_argument("--plateau", type=float, default=PLATEAU)
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--seed", type=int, default=7)
    parser.add_argument("--integrator", default="S1", choices=list(catalog.integrators()),
                        help="the catalog's integrator to run (Groot and Warren's own: GW0.65, lambda 0.65)")
    parser.add_argument("--quick", action="store_true", help=f"a run of seconds for CI: {QUICK}")
    args = parser.parse_args(argv)
    if args.quick:
        parser.set_defaults(**QUICK)
        args = parser.parse_args(argv)
    os.makedirs(args.out, exist_ok=True)
    eos, chi, profiles, plateau_series, seconds = [], [], [], [], [0.0, 0.0]

    def save():
        # after every point, so that a run cut short keeps what it measured
        if eos:
            write_csv(os.path.join(args.out, "eos.csv"), eos)
        if chi:
            write_csv(os.path.join(args.out, "chi.csv"), chi)
            write_csv(os.path.join(args.out, "profiles.csv"), profiles)
            write_csv(os.path.join(args.out, "plateau_series.csv"), plateau_series)
        with open(os.path.join(args.out, "report.md"), "w") as f:
            f.write(report(eos, chi, args, seconds))

    if "eos" in args.parts:
        start = time.time()
        for point in args.eos_points:
            a, rho, dt = (float(x) for x in point.split(":"))
            eos.append(measure_eos(a, rho, dt, args.particles, args.eos_equilibrate, args.eos_time, args.seed,
                                   args.threads, args.integrator))
            r = eos[-1]
            print(f"a {a:g} rho {rho:g} dt {dt:g}: p = {r['p']:.4f} +- {r['p_err']:.4f} "
                  f"(GW {r['p_gw']:.3f}), alpha {r['alpha']:.5f} +- {r['alpha_err']:.5f}, "
                  f"thermostat {r['p_thermostat']:+.4f}, kT {r['kT']:.4f}  [{time.time() - start:.0f} s]", flush=True)
            seconds[0] = time.time() - start
            save()
    if "chi" in args.parts:
        start = time.time()
        for point in args.chi_points:
            delta_a, dt = (float(x) for x in point.split(":"))
            row, profile, series = measure_chi(delta_a, args.slab, 3.0, dt, args.chi_equilibrate, args.chi_time,
                                       args.plateau, args.seed, args.threads, args.integrator)
            chi.append(row)
            profiles += profile
            plateau_series += series
            print(f"Delta a {delta_a:g} dt {dt:g}: phi = {row['phi']:.4f} +- {row['phi_err']:.4f} (halves "
                  f"{row['phi_first_half']:.4f} {row['phi_second_half']:.4f}), chi = {row['chi']:.3f} +- "
                  f"{row['chi_err']:.3f}, chi/Delta a = {row['chi_per_delta_a']:.4f} +- "
                  f"{row['chi_per_delta_a_err']:.4f}  [{time.time() - start:.0f} s]", flush=True)
            seconds[1] = time.time() - start
            save()
    save()
    return eos, chi


if __name__ == "__main__":
    main()
