"""A polyelectrolyte chain in a DPD solvent with its counterions and added salt: the chain's mean
squared end-to-end distance <R_ee^2> and radius of gyration <R_g^2> against the salt
concentration, beside the same chain without charges.  CPU platform, ShardlowIntegrator S1; a
CSV and a Markdown report (report.md) into docs/results/polyelectrolyte/.

    PYTHONPATH=build/python /usr/bin/python3 examples/polyelectrolyte.py [--quick] [--out DIR]

The fluid is the standard one (rho 3, a 25 between all beads, bonded ones too, gamma 4.5, kT 1,
rc 1).  The chain's beads are joined by harmonic springs F = -C r, C = 4, rest length 0 (Groot and
Madden 1998) and each carries a charge -1; as many counterions +1 and the salt's cation-anion
pairs are beads of the solvent.  The charges are Slater-smeared (openmmdpd.add_smeared_electrostatics,
lambda 0.25 rc) with Bjerrum length 1.1 rc, water at room temperature for rc = 0.646 nm (Groot
2003); every pair of charges interacts, bonded neighbours too.

Salt screens the charges along the chain: the Debye length of all the mobile ions,
kappa^-1 = (4 pi l_B rho_ions)^-1/2, falls from the counterions' alone to a bead's size, and the
chain, stretched by its own charges without salt, shrinks towards the neutral chain.  The runs
follow each other, salt-free first, each from the last one's end, and the chain without
charges last (no PME: cheap, so long).  Each average's error is the standard error of its time
series (pymbar's statistical inefficiency), the chain's positions sampled every 0.5 time
units; R_ee^2 / R_g^2 is 6 for a Gaussian coil and 12 for a rod.
"""
import argparse
import csv
import math
import os
import time

import numpy as np
import openmm

import openmmdpd
from openmmdpd import scenes
from openmmdpd.analysis import block_average, kinetic_temperature, standard_error
from openmmdpd.electrostatics import add_smeared_electrostatics, fast_pme_grid

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "..", "docs", "results", "polyelectrolyte")
DENSITY, A, GAMMA, SPRING = 3.0, 25.0, 4.5, 4.0
BJERRUM, SMEARING, FORM = 1.1, 0.25, "slater"
# PME's real-space cutoff (rc) and force tolerance: a coarser grid than the defaults' (2, 5e-4),
# since PME's reciprocal sum is most of a step's cost on the CPU platform
PME_CUTOFF, EWALD_TOLERANCE = 2.5, 1e-3
RC_NM = 0.646  # nm: three water molecules of 30 A^3 per bead at rho 3
AVOGADRO = 6.02214076e23
SAMPLE = 0.5  # time between samples of the chain's shape
# salt: the salt's ion pairs of each run, None for the chain without charges (no PME: cheap, so
# long); equilibrate and time: each run's time before and while sampling
FULL = dict(particles=5184, chain=30, dt=0.04, salt=[0, 100, 300, None], equilibrate=[40.0, 20.0, 20.0, 20.0],
            time=[200.0, 140.0, 120.0, 400.0])
QUICK = dict(particles=648, chain=10, dt=0.04, salt=[0, 60, None], equilibrate=[3.0, 3.0, 3.0],
             time=[120.0, 120.0, 120.0])


def valences(args, salt):
    """The chain (-1 each) first, then its counterions, the salt's cations and anions; 0 for the solvent."""
    z = np.zeros(args.particles)
    if salt is not None:
        n = args.chain
        z[:n], z[n:2 * n], z[2 * n:2 * n + salt], z[2 * n + salt:2 * n + 2 * salt] = -1, 1, 1, -1
    return z


def first_positions(args, seed):
    """The chain as a random walk among solvent and ions placed at random (the scene's start)."""
    positions = scenes.soft_scene(num_particles=args.particles, density=DENSITY, a=A, seed=seed).positions._value.copy()
    positions[:args.chain] = scenes.random_walk(np.random.default_rng(seed), args.chain, positions[0], args.length,
                                                bond_length=0.8, min_distance=0.5)
    return positions


def start(args, salt, equilibrate, positions, seed):
    """A Context of the chain with `salt` pairs (None: no charges at all) from `positions`, run for
    `equilibrate` time units."""
    scene = scenes.soft_scene(num_particles=args.particles, density=DENSITY, a=A, seed=seed)
    bonds = [(i, i + 1) for i in range(args.chain - 1)]
    scene.system.addForce(scenes.harmonic_bond_force(bonds, k=SPRING))
    if salt is not None:
        charges = add_smeared_electrostatics(scene.system, valences(args, salt), BJERRUM, SMEARING, FORM,
                                             cutoff=PME_CUTOFF, ewald_tolerance=EWALD_TOLERANCE)
        fast_pme_grid(charges.nonbonded, args.length)
    integrator = openmmdpd.ShardlowIntegrator(openmmdpd.reduced_temperature(1.0), GAMMA, 1.0, args.dt)
    integrator.setRandomNumberSeed(seed)
    context = openmm.Context(scene.system, integrator, openmm.Platform.getPlatformByName("CPU"),
                             {"Threads": str(args.threads)})
    context.setPositions(positions)
    context.setVelocitiesToTemperature(openmmdpd.reduced_temperature(1.0), seed)
    integrator.step(round(equilibrate / args.dt))
    return context, integrator


def chain_shape(x, length):
    """(R_ee^2, R_g^2) of the chain x (beads in bond order), made whole bond by bond (minimum image)."""
    bonds = np.diff(x, axis=0)
    bonds -= length * np.round(bonds / length)
    whole = np.vstack([x[:1], x[:1] + np.cumsum(bonds, axis=0)])
    end_to_end = whole[-1] - whole[0]
    return float(end_to_end @ end_to_end), float(np.mean(np.sum((whole - whole.mean(axis=0)) ** 2, axis=1)))


def measure(args, salt, equilibrate, time_span, positions, seed):
    """One run's row, and its last positions."""
    context, integrator = start(args, salt, equilibrate, positions, seed)
    shapes, temperatures, bond_lengths = [], [], []
    for _ in range(round(time_span / SAMPLE)):
        integrator.step(round(SAMPLE / args.dt))
        state = context.getState(getPositions=True, getVelocities=True)
        x = state.getPositions(asNumpy=True)._value[:args.chain]
        shapes.append(chain_shape(x, args.length))
        d = np.diff(x, axis=0)
        d -= args.length * np.round(d / args.length)
        bond_lengths.append(float(np.mean(np.sqrt(np.sum(d * d, axis=1)))))
        temperatures.append(kinetic_temperature(state.getVelocities(asNumpy=True)._value, np.ones(args.particles)))
    ree2, rg2 = np.array(shapes).T
    positions = state.getPositions(asNumpy=True)._value
    volume = args.length ** 3
    ions = 0 if salt is None else args.chain + 2 * salt
    return dict(salt=-1 if salt is None else salt, salt_density=(salt or 0) / volume,
                molar=(salt or 0) / volume / (AVOGADRO * (RC_NM * 1e-8) ** 3),
                debye_length=math.inf if ions == 0 else 1 / math.sqrt(4 * math.pi * BJERRUM * ions / volume),
                ree2=float(ree2.mean()), ree2_err=standard_error(ree2), ree2_err_blocks=block_average(ree2, 8)[1],
                rg2=float(rg2.mean()), rg2_err=standard_error(rg2), rg2_err_blocks=block_average(rg2, 8)[1],
                ratio=float(ree2.mean() / rg2.mean()), bond=float(np.mean(bond_lengths)),
                bond_err=standard_error(bond_lengths), samples=len(ree2),
                kT=float(np.mean(temperatures)), kT_err=standard_error(temperatures)), positions


def measure_all(args):
    """The runs in turn, each from the last one's end: the chain shrinks from run to run, so each
    starts nearer its own state than from a random walk, and what it keeps of the last can only
    make the fall with salt smaller."""
    rows, positions = [], first_positions(args, args.seed)
    for k, (salt, equilibrate, span) in enumerate(zip(args.salt, args.equilibrate, args.time)):
        t0 = time.perf_counter()
        row, positions = measure(args, salt, equilibrate, span, positions, seed=args.seed + k)
        row["seconds"] = time.perf_counter() - t0
        rows.append(row)
        print(f"{label(row)}: Debye length {row['debye_length']:.3g}, <R_ee^2> {row['ree2']:.2f} +- {row['ree2_err']:.2f}, "
              f"<R_g^2> {row['rg2']:.3f} +- {row['rg2_err']:.3f}, bond {row['bond']:.3f} +- {row['bond_err']:.3f}, kT {row['kT']:.4f}; "
              f"{row['seconds']:.0f} s", flush=True)
    return rows


def label(row):
    return "no charges" if row["salt"] < 0 else f"{row['salt']} salt pairs"


def write(rows, args):
    os.makedirs(args.out, exist_ok=True)
    with open(os.path.join(args.out, "polyelectrolyte.csv"), "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows({k: f"{v:.6g}" for k, v in row.items()} for row in rows)
    lines = [
        "# Polyelectrolyte chain against added salt",
        "",
        f"One chain of {args.chain} beads (charge -1 each, springs C = {SPRING:g}) with {args.chain} counterions "
        f"in the standard fluid (rho {DENSITY:g}, a {A:g}, gamma {GAMMA:g}, kT 1, rc 1), N = {args.particles} "
        f"(L = {args.length:.3g}); {FORM} smearing lambda {SMEARING:g}, l_B {BJERRUM:g}; ShardlowIntegrator S1 at "
        f"dt {args.dt:g}. The runs follow each other in the order below, each from the last one's end (the first "
        f"from a random walk): equilibrated for the first time given, then sampled every {SAMPLE:g} for the second.",
        "Errors are one standard error (pymbar's statistical inefficiency; the error from 8 block means beside it). "
        "Made by `examples/polyelectrolyte.py" + (" --quick" if args.quick else "") + "`.",
        "",
        "| chain | salt pairs | c_salt (mol/L) | Debye length | time | <R_ee^2> | 8 blocks | <R_g^2> | 8 blocks | "
        "R_ee^2 / R_g^2 | mean bond | kT |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r, equilibrate, span in zip(rows, args.equilibrate, args.time):
        charged = r["salt"] >= 0
        lines.append(f"| {'charged' if charged else 'neutral'} | {r['salt'] if charged else '-'} | "
                     f"{r['molar']:.3f} | {r['debye_length']:.2f} | {equilibrate:g} + {span:g} | "
                     f"{r['ree2']:.2f} ± {r['ree2_err']:.2f} | {r['ree2_err_blocks']:.2f} | "
                     f"{r['rg2']:.3f} ± {r['rg2_err']:.3f} | {r['rg2_err_blocks']:.3f} | {r['ratio']:.2f} | "
                     f"{r['bond']:.3f} | {r['kT']:.4f} ± {r['kT_err']:.4f} |")
    with open(os.path.join(args.out, "report.md"), "w") as f:
        f.write("\n".join(lines) + "\n")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="seconds: a short chain in a small box, short runs")
    parser.add_argument("--out", default=OUT, help="output folder")
    parser.add_argument("--threads", type=int, default=2, help="CPU platform threads")
    parser.add_argument("--seed", type=int, default=41, help="the first run's random seed; run k takes seed + k")
    args = parser.parse_args(argv)
    for key, value in (QUICK if args.quick else FULL).items():
        setattr(args, key, value)
    args.length = (args.particles / DENSITY) ** (1 / 3)
    rows = measure_all(args)
    write(rows, args)
    return rows


if __name__ == "__main__":
    main()
