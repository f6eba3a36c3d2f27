"""<kT> against the time step on a scene, for each DPDVVIntegrator variant (paper 000 Fig. 1/4).

Each run: equilibrate, then sample the kinetic temperature every 5 steps over a simulated
time that shrinks the standard error to ~0.001; block averages give the error."""
import argparse

import numpy as np
import openmm
from openmm import unit

import openmmdpd
from openmmdpd import analysis, scenes

VARIANTS = {"gw0.5": (openmmdpd.DPDVVIntegrator.GrootWarren, 0.5), "gw0.65": (openmmdpd.DPDVVIntegrator.GrootWarren, 0.65),
            "dpdvv": (openmmdpd.DPDVVIntegrator.DPDVV, 0.5), "scvv": (openmmdpd.DPDVVIntegrator.SelfConsistent, 0.5)}


def measure(scene, variant, lam, dt, time_span, threads, seed=7):
    integrator = openmmdpd.DPDVVIntegrator(openmmdpd.KT_TEMPERATURE, 4.5, 1.0, dt)
    integrator.setVariant(variant)
    integrator.setLambda(lam)
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
    parser.add_argument("--variants", nargs="+", default=["gw0.5"], choices=sorted(VARIANTS))
    parser.add_argument("--time", type=float, default=80.0, help="sampled time per run (reduced units)")
    parser.add_argument("--threads", type=int, default=1)
    args = parser.parse_args(argv)
    scene = scenes.build_scene(args.scene, num_particles=args.particles)
    print(f"scene {args.scene}, N = {args.particles}, gamma = 4.5, rc = 1, sampled time {args.time}")
    print(f"{'variant':>8} {'dt':>6} {'<kT>':>8} {'stderr':>8}")
    for name in args.variants:
        variant, lam = VARIANTS[name]
        for dt in args.dts:
            try:
                mean, err = measure(scene, variant, lam, dt, args.time, args.threads)
                print(f"{name:>8} {dt:>6} {mean:>8.4f} {err:>8.4f}", flush=True)
            except openmm.OpenMMException as error:
                print(f"{name:>8} {dt:>6} unstable: {str(error)[:80]}", flush=True)


if __name__ == "__main__":
    main()
