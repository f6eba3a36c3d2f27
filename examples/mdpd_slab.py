"""A many-body DPD liquid film in coexistence with its vapour, at Warren's parameters
(A = -40, B = 25, rd = 0.75, rc = 1, kT = 1; Warren 2003): the coexisting liquid and vapour
densities and the surface tension, each with its standard error.  CPU platform,
ShardlowIntegrator S1 (gamma 4.5, dt 0.01); a CSV and a Markdown report into
docs/results/mdpd-slab/.

    PYTHONPATH=build/python /usr/bin/python3 examples/mdpd_slab.py [--quick] [--out DIR]

The film spans the box in x and y and has two free surfaces normal to z.  Each sample
records the density profile along z about the film's centre (the circular mean of z, so the
film may drift) and the pressure tensor averaged since the last sample; the liquid density
is the profile's mean within the film's core (more than CORE from either surface), the
vapour's beyond VAPOUR of them, and the surface tension, by mechanical equilibrium of a film
with two surfaces, gamma = (Lz / 2) (P_zz - (P_xx + P_yy) / 2).  Errors: pymbar's statistical
inefficiency over the samples (openmmdpd.analysis.standard_error).
"""
import argparse
import csv
import math
import os
import time

import numpy as np
import openmm

import openmmdpd
from openmmdpd.analysis import standard_error

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "..", "docs", "results", "mdpd-slab")
A, B, RD, KT, GAMMA, DT = -40.0, 25.0, 0.75, 1.0, 4.5, 0.01
START_DENSITY = 6.0  # the film is filled at about the liquid's density
CORE, VAPOUR = 1.5, 2.5  # distances inside and outside the film's nominal surfaces (nm)
FULL = dict(width=6.0, thickness=8.0, equilibrate=100.0, sample=1000.0, interval=1.0)
QUICK = dict(width=4.0, thickness=5.0, equilibrate=2.0, sample=4.0, interval=0.5)


def build(width, thickness, seed=1):
    """System and positions: a film of `thickness` across a width x width x 3 thickness box."""
    height = 3 * thickness
    n = int(round(START_DENSITY * width * width * thickness))
    rng = np.random.default_rng(seed)
    positions = rng.uniform(0, 1, (n, 3)) * [width, width, thickness] + [0, 0, thickness]
    system = openmm.System()
    system.setDefaultPeriodicBoxVectors(openmm.Vec3(width, 0, 0), openmm.Vec3(0, width, 0), openmm.Vec3(0, 0, height))
    for _ in range(n):
        system.addParticle(1.0)
    system.addForce(openmmdpd.MDPDForce(A, B, 1.0, RD))
    return system, positions, height


def centred_heights(z, height):
    """|z - centre| (nearest image) about the film's centre, the circular mean of z."""
    angle = 2 * np.pi * z / height
    centre = height / (2 * np.pi) * math.atan2(np.sin(angle).mean(), np.cos(angle).mean())
    d = z - centre
    return np.abs(d - height * np.round(d / height))


def sample(args, system, positions, height):
    """Per sample: (liquid density, vapour density, surface tension)."""
    integrator = openmmdpd.ShardlowIntegrator(openmmdpd.reduced_temperature(KT), GAMMA, 1.0, DT)
    integrator.setRandomNumberSeed(7)
    context = openmm.Context(system, integrator, openmm.Platform.getPlatformByName("CPU"), {"Threads": str(args.threads)})
    context.setPositions(positions)
    context.setVelocitiesToTemperature(openmmdpd.reduced_temperature(KT), 3)
    integrator.step(int(round(args.equilibrate / DT)))
    integrator.setPressureTensorEnabled(True)
    area, half = args.width ** 2, args.thickness / 2
    rows = []
    for _ in range(int(round(args.sample / args.interval))):
        integrator.resetPressureTensor()
        integrator.step(int(round(args.interval / DT)))
        p = np.array(integrator.getAveragePressureTensor(integrator.PressureTotal)._value)
        z = context.getState(getPositions=True).getPositions(asNumpy=True)._value[:, 2]
        h = centred_heights(z, height)
        core, far = h < half - CORE, h > half + VAPOUR
        rows.append((np.sum(core) / (area * 2 * (half - CORE)),
                     np.sum(far) / (area * (height - 2 * (half + VAPOUR))),
                     height / 2 * (p[2] - 0.5 * (p[0] + p[1]))))
    return np.array(rows)


def write(result, args, seconds):
    os.makedirs(args.out, exist_ok=True)
    names = ["liquid density", "vapour density", "surface tension"]
    with open(os.path.join(args.out, "mdpd-slab.csv"), "w", newline="") as f:
        out = csv.writer(f)
        out.writerow(["quantity", "value", "error"])
        for name, (value, error) in zip(names, result):
            out.writerow([name, f"{value:.5g}", f"{error:.2g}"])
    lines = [f"# MDPD liquid film at A = {A:g}, B = {B:g}, rd = {RD:g}, kT = {KT:g}", "",
             f"{args.particles} particles, film {args.thickness:g} thick in a {args.width:g} x {args.width:g} x "
             f"{3 * args.thickness:g} box; S1, gamma {GAMMA:g}, dt {DT:g}; {args.equilibrate:g} time units to "
             f"equilibrate, {args.sample:g} sampled every {args.interval:g}; {seconds:.0f} s.", "",
             "| quantity | value |", "|---|---|"]
    lines += [f"| {name} | {value:.4g} ± {error:.2g} |" for name, (value, error) in zip(names, result)]
    with open(os.path.join(args.out, "report.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="seconds: a small film and short runs")
    parser.add_argument("--out", default=OUT, help="output folder")
    parser.add_argument("--threads", type=int, default=2, help="CPU platform threads")
    args = parser.parse_args(argv)
    for key, value in (QUICK if args.quick else FULL).items():
        setattr(args, key, value)
    start = time.time()
    system, positions, height = build(args.width, args.thickness)
    args.particles = system.getNumParticles()
    rows = sample(args, system, positions, height)
    result = [(float(rows[:, k].mean()), standard_error(rows[:, k])) for k in range(3)]
    write(result, args, time.time() - start)
    return result


if __name__ == "__main__":
    main()
