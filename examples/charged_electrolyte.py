"""A 1:1 electrolyte of smeared-charge DPD beads in a neutral DPD solvent at several salt
concentrations: the electrostatic energy per ion beside Debye-Hueckel theory, and the
cation-anion and cation-cation radial distribution functions.  CPU platform,
ShardlowIntegrator S1; a CSV per quantity and a Markdown report (report.md) into
docs/results/charged-electrolyte/.

    PYTHONPATH=build/python /usr/bin/python3 examples/charged_electrolyte.py [--quick] [--out DIR]

The fluid is the standard one (rho 3, a 25 between all beads, gamma 4.5, kT 1, rc 1).  Cations
(+1) and anions (-1) carry Slater-smeared charges (openmmdpd.add_smeared_electrostatics,
lambda 0.25 rc) with Bjerrum length 1.1 rc: water at room temperature with rc = 0.646 nm,
three water molecules per bead (Groot 2003; Gonzalez-Melchor et al. 2006).

The energy per ion is the electrostatic forces' energy over the number of ions, its error from
pymbar's statistical inefficiency.  Theory, for ions of total density rho_i and inverse Debye
length kappa = sqrt(4 pi l_B rho_i):
- the Debye-Hueckel limiting law, u = -l_B kappa / 2 (point ions, kappa -> 0);
- extended Debye-Hueckel, u = -l_B kappa / (2 (1 + kappa a)), with a = 35 lambda / 32: the a at
  which it agrees to order kappa^2 with the linearised (Debye-Hueckel, random-phase) theory of
  these smeared charges, u = -(l_B kappa^2 / pi) int F^2 / (k^2 + kappa^2 F) dk, F(k) =
  (1 + k^2 lambda^2 / 4)^-2 the Fourier transform of the Slater pair form;
- the same linearised theory in the simulation's periodic box: its sum over the box's
  wavevectors, without k = 0, plus the Ewald self-energy of an ion with its images (cubic
  Madelung constant 2.837297, Hummer, Pratt and Garcia 1996), as the Ewald sum counts it.
All three leave out the soft repulsion between ions and hold at low concentration, where
kappa l_B and kappa a are small.  The radial distribution functions g+- and g++ stand beside
exp(+w) and exp(-w), w(r) the linearised theory's potential of mean force of two ions.
"""
import argparse
import csv
import math
import os
import time

import numpy as np
import openmm
from scipy import integrate

import openmmdpd
from openmmdpd import scenes
from openmmdpd.analysis import block_average, kinetic_temperature, standard_error
from openmmdpd.electrostatics import add_smeared_electrostatics, fast_pme_grid

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "..", "docs", "results", "charged-electrolyte")
DENSITY, A, GAMMA = 3.0, 25.0, 4.5
BJERRUM, SMEARING, FORM = 1.1, 0.25, "slater"
# PME's real-space cutoff (rc) and force tolerance: a coarser grid than the defaults' (2, 5e-4),
# since PME's reciprocal sum is most of a step's cost on the CPU platform
PME_CUTOFF, EWALD_TOLERANCE = 2.5, 1e-3
RC_NM = 0.646  # nm: three water molecules of 30 A^3 per bead at rho 3
AVOGADRO = 6.02214076e23
MADELUNG = 2.837297479  # simple cubic lattice of unit charges in a neutralising background
SAMPLE = 0.5  # time between samples of the energy and the ions' positions
RDF_BIN = 0.05
# salt: ion pairs in the box, one run each; time: the sampling time of each run
FULL = dict(particles=3000, dt=0.02, equilibrate=10.0, salt=[5, 15, 45, 150], time=[250.0, 130.0, 90.0, 50.0])
QUICK = dict(particles=648, dt=0.02, equilibrate=2.0, salt=[6, 30], time=[8.0, 6.0])


def inverse_debye_length(ions, volume):
    return math.sqrt(4 * math.pi * BJERRUM * ions / volume)


def pair_transform(k):
    """F(k), the Slater pair form's Coulomb energy over the point charges' (1 at k = 0)."""
    return (1 + (k * SMEARING / 2) ** 2) ** -2


def linearised_energy(kappa):
    """The Debye-Hueckel (random-phase) energy per ion of the smeared charges, infinite system."""
    value, _ = integrate.quad(lambda k: pair_transform(k) ** 2 / (k * k + kappa ** 2 * pair_transform(k)),
                              0, np.inf, limit=200)
    return -BJERRUM * kappa ** 2 / math.pi * value


def linearised_energy_in_box(kappa, length, modes=40):
    """The same theory in a periodic cube of edge `length`, summed as the Ewald sum counts it: the
    ions' correlation over the wavevectors 2 pi n / L, n != 0, plus half the self-energy of an
    ion with its images and the background, for the smeared pair form."""
    n = np.arange(-modes, modes + 1)
    k2 = (2 * math.pi / length) ** 2 * (n[:, None, None] ** 2 + n[None, :, None] ** 2 + n[None, None, :] ** 2)
    k2 = k2[k2 > 0].astype(float)
    f = pair_transform(np.sqrt(k2))
    coulomb = 4 * math.pi * BJERRUM * f / k2
    correlation = 0.5 * np.sum(coulomb * (-kappa ** 2 * f / (k2 + kappa ** 2 * f))) / length ** 3
    self_energy = -MADELUNG * BJERRUM / (2 * length) + math.pi * BJERRUM * SMEARING ** 2 / length ** 3
    return correlation + self_energy


def screened_potential(r, kappa):
    """The same theory's potential of mean force between two unit charges at distance r > 0 (kT,
    infinite system): the inverse Fourier transform of v(k) / (1 + kappa^2 F(k) / k^2)."""
    value, _ = integrate.quad(lambda k: 4 * math.pi * BJERRUM * k * pair_transform(k) / (k * k + kappa ** 2 * pair_transform(k)),
                              0, np.inf, weight="sin", wvar=r)
    return value / (2 * math.pi ** 2 * r)


def theory(ions, length):
    kappa = inverse_debye_length(ions, length ** 3)
    size = 35 * SMEARING / 32
    return dict(kappa=kappa, debye_length=1 / kappa, limiting_law=-BJERRUM * kappa / 2,
                extended_dh=-BJERRUM * kappa / (2 * (1 + kappa * size)), linearised=linearised_energy(kappa),
                linearised_box=linearised_energy_in_box(kappa, length))


def start(args, pairs, seed):
    """A Context of the fluid with `pairs` cations (the first beads) and as many anions (the next)."""
    scene = scenes.soft_scene(num_particles=args.particles, density=DENSITY, a=A, seed=seed)
    valences = np.zeros(args.particles)
    valences[:pairs], valences[pairs:2 * pairs] = 1, -1
    charges = add_smeared_electrostatics(scene.system, valences, BJERRUM, SMEARING, FORM,
                                         cutoff=PME_CUTOFF, ewald_tolerance=EWALD_TOLERANCE)
    charges.set_force_group(1)
    fast_pme_grid(charges.nonbonded, args.length)
    integrator = openmmdpd.ShardlowIntegrator(openmmdpd.reduced_temperature(1.0), GAMMA, 1.0, args.dt)
    integrator.setRandomNumberSeed(seed)
    context = openmm.Context(scene.system, integrator, openmm.Platform.getPlatformByName("CPU"),
                             {"Threads": str(args.threads)})
    context.setPositions(scene.positions)
    context.setVelocitiesToTemperature(openmmdpd.reduced_temperature(1.0), seed)
    integrator.step(round(args.equilibrate / args.dt))
    return context, integrator


def pair_histograms(frames, pairs, length, edges):
    """Histograms of the cation-anion and cation-cation distances (minimum image) over frames."""
    cross, like = np.zeros(len(edges) - 1), np.zeros(len(edges) - 1)
    upper = np.triu_indices(pairs, 1)
    for x in frames:
        cations, anions = x[:pairs], x[pairs:2 * pairs]
        for histogram, d in ((cross, cations[:, None] - anions[None]), (like, (cations[:, None] - cations[None])[upper])):
            d -= length * np.round(d / length)
            histogram += np.histogram(np.sqrt(np.sum(d * d, axis=-1)), bins=edges)[0]
    return cross, like


def radial_distributions(frames, pairs, length):
    """(r, g_+-, g_++): each histogram over the count a uniform fluid of the same ions puts in its shell."""
    edges = np.arange(0.0, min(4.0, length / 2) + RDF_BIN / 2, RDF_BIN)
    cross, like = pair_histograms(frames, pairs, length, edges)
    shells = 4 * math.pi / 3 * np.diff(edges ** 3) / length ** 3 * len(frames)
    return 0.5 * (edges[1:] + edges[:-1]), cross / (pairs * pairs * shells), like / (pairs * (pairs - 1) / 2 * shells)


def measure(args, pairs, time_span, seed):
    context, integrator = start(args, pairs, seed)
    energies, temperatures, frames = [], [], []
    for _ in range(round(time_span / SAMPLE)):
        integrator.step(round(SAMPLE / args.dt))
        state = context.getState(getEnergy=True, getPositions=True, getVelocities=True, groups={1})
        energies.append(state.getPotentialEnergy()._value / (2 * pairs))
        temperatures.append(kinetic_temperature(state.getVelocities(asNumpy=True)._value, np.ones(args.particles)))
        frames.append(state.getPositions(asNumpy=True)._value[:2 * pairs].copy())
    energies = np.array(energies)
    r, g_cross, g_like = radial_distributions(frames, pairs, args.length)
    row = dict(pairs=pairs, ion_density=2 * pairs / args.length ** 3,
               molar=pairs / args.length ** 3 / (AVOGADRO * (RC_NM * 1e-8) ** 3), samples=len(energies),
               energy=float(energies.mean()), energy_err=standard_error(energies),
               energy_err_blocks=block_average(energies, 8)[1], kT=float(np.mean(temperatures)),
               kT_err=standard_error(temperatures), g_cross_peak=float(g_cross.max()),
               r_cross_peak=float(r[np.argmax(g_cross)]))
    row.update(theory(2 * pairs, args.length))
    return row, (r, g_cross, g_like)


def measure_all(args):
    rows, distributions = [], []
    for k, (pairs, span) in enumerate(zip(args.salt, args.time)):
        t0 = time.perf_counter()
        row, rdf = measure(args, pairs, span, seed=21 + k)
        row["seconds"] = time.perf_counter() - t0
        rows.append(row)
        distributions.append(rdf)
        print(f"{pairs} pairs ({row['molar']:.3f} M): energy per ion {row['energy']:.4f} +- {row['energy_err']:.4f} kT; "
              f"limiting law {row['limiting_law']:.4f}, extended DH {row['extended_dh']:.4f}, "
              f"in the box {row['linearised_box']:.4f}; kT {row['kT']:.4f}; {row['seconds']:.0f} s", flush=True)
    return rows, distributions


def write_csvs(rows, distributions, args):
    """energy.csv, a row per concentration; rdf.csv, g+- and g++ measured and of the linearised
    theory, exp(+-w(r)), a column each per concentration."""
    os.makedirs(args.out, exist_ok=True)
    with open(os.path.join(args.out, "energy.csv"), "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows({k: f"{v:.6g}" for k, v in row.items()} for row in rows)
    names = ("g_cation_anion", "g_cation_cation", "dh_cation_anion", "dh_cation_cation")
    r = distributions[0][0]
    columns = []
    for row, (_, cross, like) in zip(rows, distributions):
        w = np.array([screened_potential(x, row["kappa"]) for x in r])
        columns += [cross, like, np.exp(w), np.exp(-w)]
    with open(os.path.join(args.out, "rdf.csv"), "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(["r"] + [f"{name}_{row['pairs']}" for row in rows for name in names])
        for i in range(len(r)):
            writer.writerow([f"{r[i]:.3f}"] + [f"{g[i]:.5g}" for g in columns])


def write_report(rows, distributions, args):
    lines = [
        "# Energy per ion of a smeared-charge 1:1 electrolyte",
        "",
        f"rho {DENSITY:g}, a {A:g}, gamma {GAMMA:g}, kT 1, rc 1, N = {args.particles} (L = {args.length:.3g}); "
        f"{FORM} smearing lambda {SMEARING:g}, l_B {BJERRUM:g}; ShardlowIntegrator S1 at dt {args.dt:g}, "
        f"{args.equilibrate:g} time units to equilibrate, a sample every {SAMPLE:g}.",
        "Errors are one standard error (pymbar's statistical inefficiency). Made by "
        "`examples/charged_electrolyte.py" + (" --quick" if args.quick else "") + "`.",
        "",
        "| ion pairs | c (mol/L) | kappa l_B | time | energy per ion (kT) | sigma, 8 blocks | limiting law | "
        "extended DH | linearised, this box | (measured - box) / sigma | g+- peak (r) | kT |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for row, span in zip(rows, args.time):
        lines.append(f"| {row['pairs']} | {row['molar']:.3f} | {row['kappa'] * BJERRUM:.2f} | {span:g} | "
                     f"{row['energy']:.4f} ± {row['energy_err']:.4f} | {row['energy_err_blocks']:.4f} | "
                     f"{row['limiting_law']:.4f} | "
                     f"{row['extended_dh']:.4f} | {row['linearised_box']:.4f} | "
                     f"{(row['energy'] - row['linearised_box']) / row['energy_err']:+.1f} | "
                     f"{row['g_cross_peak']:.2f} ({row['r_cross_peak']:.2f}) | {row['kT']:.4f} ± {row['kT_err']:.4f} |")
    r = distributions[0][0]
    lines += ["", "Radial distribution functions at a few distances (bins of width "
              f"{RDF_BIN:g}; rdf.csv has them all), beside the linearised theory's exp(+-w(r)), w its "
              "potential of mean force of two ions, which leaves out the soft repulsion:", "",
              "| ion pairs | r | g+- | g+- linearised | g++ | g++ linearised |", "|---|---|---|---|---|---|"]
    for row, (_, cross, like) in zip(rows, distributions):
        for target in (0.525, 1.025, 1.525, 2.025):
            i = int(np.argmin(np.abs(r - target)))
            w = screened_potential(r[i], row["kappa"])
            lines.append(f"| {row['pairs']} | {r[i]:.3f} | {cross[i]:.3f} | {math.exp(w):.3f} | {like[i]:.3f} | "
                         f"{math.exp(-w):.3f} |")
    with open(os.path.join(args.out, "report.md"), "w") as f:
        f.write("\n".join(lines) + "\n")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="seconds: a small box and short runs")
    parser.add_argument("--out", default=OUT, help="output folder")
    parser.add_argument("--threads", type=int, default=2, help="CPU platform threads")
    args = parser.parse_args(argv)
    for key, value in (QUICK if args.quick else FULL).items():
        setattr(args, key, value)
    args.length = (args.particles / DENSITY) ** (1 / 3)
    rows, distributions = measure_all(args)
    write_csvs(rows, distributions, args)
    write_report(rows, distributions, args)
    return rows


if __name__ == "__main__":
    main()
