"""<kT> against the time step on a scene, for any of the integrators (Nikunen et al. 2003, Figs. 1 and 4).

Each run: equilibrate, then sample the kinetic temperature every 5 steps over a simulated
time that shrinks the standard error to ~0.001; block averages give the error."""
import argparse

import numpy as np
import openmm
from openmm import unit

import openmmdpd
from openmmdpd import analysis, catalog, scenes

def measure(scene, make, dt, time_span, threads, seed=7):
    integrator = make(dt)
    if hasattr(integrator, "setRandomNumberSeed"):
        integrator.setRandomNumberSeed(seed)
    context = openmm.Context(scene.system, integrator, openmm.Platform.getPlatformByName("CPU"), {"Threads": str(threads)})
    context.setPositions(scene.positions)
    context.setVelocitiesToTemperature(openmmdpd.KT_TEMPERATURE, seed)
    integrator.step(int(5 / dt))
    dof = 3 * scene.system.getNumParticles() - 3
    samples = []
    for _ in range(int(time_span / dt / 5)):
        integrator.step(5)
        ke = context.getState(getEnergy=True).getKineticEnergy().value_in_unit(unit.kilojoule_per_mole)
        samples.append(2 * ke / dof)
    return analysis.block_average(np.array(samples), nblocks=20)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--scene", default="soft")
    parser.add_argument("--particles", type=int, default=4000)
    parser.add_argument("--dts", type=float, nargs="+", default=[0.01, 0.02, 0.03, 0.05, 0.07])
    parser.add_argument("--integrators", nargs="+", default=["GW"], choices=list(catalog.integrators()))
    parser.add_argument("--time", type=float, default=80.0, help="sampled time per run (reduced units)")
    parser.add_argument("--threads", type=int, default=1)
    args = parser.parse_args(argv)
    scene = scenes.build_scene(args.scene, num_particles=args.particles)
    print(f"scene {args.scene}, N = {args.particles}, gamma = 4.5, rc = 1, sampled time {args.time}")
    print(f"{'integrator':>10} {'dt':>6} {'<kT>':>8} {'stderr':>8}")
    factories = catalog.integrators()
    for name in args.integrators:
        for dt in args.dts:
            try:
                mean, err = measure(scene, factories[name], dt, args.time, args.threads)
                print(f"{name:>10} {dt:>6} {mean:>8.4f} {err:>8.4f}", flush=True)
            except openmm.OpenMMException as error:
                print(f"{name:>10} {dt:>6} unstable: {str(error)[:80]}", flush=True)


if __name__ == "__main__":
    main()
