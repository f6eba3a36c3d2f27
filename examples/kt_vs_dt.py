"""Kinetic and configurational kT against the time step on model A (scene `ideal`) or model B
(scene `soft`: rho 4, a 25, gamma 4.5): GW-1/2, S1, Lowe, pair OU, both pair thermostats in
the middle splitting (LoweAndersenIntegrator.setSplitting(Middle)) and den Otter-Clarke with
the averages of Nikunen et al. 2003, Table III, all in one run; a markdown table on stdout.

    PYTHONPATH=build/python /usr/bin/python3 examples/kt_vs_dt.py [--scene soft] [--particles 4000] [--time 30] [--quick]

kT_conf = <sum |F|^2> / <sum lap U> (Rugh's configurational temperature of the soft
repulsion; none on model A).  Errors: the standard error of the mean from pymbar's
statistical inefficiency (for kT_conf, of the linearised ratio sum|F|^2 - R sum lap U,
divided by <sum lap U>).
"""
import argparse

import numpy as np
import openmm
from openmm import unit

from openmmdpd import catalog, options, scenes
from openmmdpd.analysis import ratio_with_error, standard_error
from openmmdpd.compare import soft_repulsion_laplacian

NAMES = ["GW", "S1", "Lowe", "PairOU", "Lowe-mid", "PairOU-mid", "OC"]
DTS = [0.02, 0.05, 0.1]
SAMPLE_INTERVAL = 0.1   # ps
# --quick's defaults (options.parse_args)
QUICK = dict(particles=500, time=3.0, equilibrate=3.0, integrators=["GW", "Lowe-mid"], dts=[0.05])


def measure(name, dt, scene, sample_time, equilibration, seed):
    integrator = catalog.integrators(scene.name)[name](dt)
    integrator.setRandomNumberSeed(seed)
    context = openmm.Context(scene.system, integrator, openmm.Platform.getPlatformByName("CPU"))
    context.setPositions(scene.positions)
    context.setVelocitiesToTemperature(catalog.KT_TEMPERATURE, seed)
    n = scene.system.getNumParticles()
    length = scene.system.getDefaultPeriodicBoxVectors()[0][0].value_in_unit(unit.nanometer)
    integrator.step(round(equilibration / dt))
    every = max(1, round(SAMPLE_INTERVAL / dt))
    kinetic, force2, laplacian = [], [], []
    for _ in range(round(sample_time / SAMPLE_INTERVAL)):
        integrator.step(every)
        state = context.getState(getEnergy=True, getPositions=True)
        ke = state.getKineticEnergy().value_in_unit(unit.kilojoule_per_mole)
        kinetic.append(2 * ke / (3 * n - 3))
        if scene.name == "soft":
            f2, lap = soft_repulsion_laplacian(state.getPositions(asNumpy=True).value_in_unit(unit.nanometer), length)
            force2.append(f2)
            laplacian.append(lap)
    kinetic = np.array(kinetic)
    if not laplacian:
        return kinetic.mean(), standard_error(kinetic), None, None
    return (kinetic.mean(), standard_error(kinetic)) + ratio_with_error(force2, laplacian)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--scene", choices=["ideal", "soft"], default="soft")
    parser.add_argument("--particles", type=int, default=4000)
    parser.add_argument("--time", type=float, default=30.0, help="sampled ps per run")
    parser.add_argument("--equilibrate", type=float, default=5.0, help="ps each run equilibrates before sampling")
    parser.add_argument("--integrators", nargs="+", default=NAMES, choices=NAMES)
    parser.add_argument("--dts", type=float, nargs="+", default=DTS)
    parser.add_argument("--seed", type=int, default=3)
    options.add_quick(parser, QUICK)
    args = options.parse_args(parser, argv, QUICK)
    scene = scenes.build_scene(args.scene, num_particles=args.particles)
    model = {"ideal": "model A", "soft": "model B"}[args.scene]
    print(f"{model} (scene {args.scene}), N = {args.particles}, {args.time:g} ps sampled per run after "
          f"{args.equilibrate:g} ps, seed {args.seed}\n")
    print("| integrator | dt | kinetic kT | configurational kT |")
    print("|---|---|---|---|")
    for name in args.integrators:
        for dt in args.dts:
            try:
                kt, kt_err, conf, conf_err = measure(name, dt, scene, args.time, args.equilibrate, args.seed)
                conf_text = "" if conf is None else f"{conf:.4f} ± {conf_err:.4f}"
                print(f"| {name} | {dt:g} | {kt:.4f} ± {kt_err:.4f} | {conf_text} |", flush=True)
            except openmm.OpenMMException as error:
                print(f"| {name} | {dt:g} | unstable: {str(error).splitlines()[0][:60]} | |", flush=True)

if __name__ == "__main__":
    main()
