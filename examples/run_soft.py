"""Scene `soft` (DPD fluid, a = 25, rho = 4) with DPDVVIntegrator, in reduced units, as an
ordinary OpenMM script: prints <kT> with its standard error (it should be 1 at small dt)."""
import argparse
import sys

import numpy as np
import openmm
from openmm import app, unit

import openmmdpd
from openmmdpd import analysis, scenes

VARIANTS = {"gw": openmmdpd.DPDVVIntegrator.GrootWarren, "dpdvv": openmmdpd.DPDVVIntegrator.DPDVV,
            "scvv": openmmdpd.DPDVVIntegrator.SelfConsistent}


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--particles", type=int, default=4000)
    parser.add_argument("--dt", type=float, default=0.04, help="time step (reduced units = ps)")
    parser.add_argument("--steps", type=int, default=2000)
    parser.add_argument("--equilibrate", type=int, default=500)
    parser.add_argument("--variant", choices=sorted(VARIANTS), default="gw")
    parser.add_argument("--platform", default="CPU")
    args = parser.parse_args(argv)

    scene = scenes.build_scene("soft", num_particles=args.particles)
    # gamma = 4.5 (sigma = 3), rc = 1, kT = 1: friction in 1/ps equals gamma for unit masses.
    integrator = openmmdpd.DPDVVIntegrator(openmmdpd.KT_TEMPERATURE, 4.5 / unit.picosecond,
                                           1.0 * unit.nanometer, args.dt * unit.picosecond)
    integrator.setVariant(VARIANTS[args.variant])
    integrator.setRandomNumberSeed(2024)
    simulation = app.Simulation(scene.topology, scene.system, integrator, openmm.Platform.getPlatformByName(args.platform))
    simulation.context.setPositions(scene.positions)
    simulation.context.setVelocitiesToTemperature(openmmdpd.KT_TEMPERATURE, 1)
    simulation.step(args.equilibrate)

    dof = 3 * args.particles - 3
    samples = []
    for _ in range(args.steps // 10):
        simulation.step(10)
        kinetic = simulation.context.getState(getEnergy=True).getKineticEnergy()
        samples.append(2 * kinetic.value_in_unit(unit.kilojoule_per_mole) / dof)
    mean, error = analysis.block_average(np.array(samples))
    print(f"scene soft, N = {args.particles}, dt = {args.dt}, variant {args.variant}, {args.platform}: "
          f"<kT> = {mean:.4f} +- {error:.4f} over {args.steps} steps")


if __name__ == "__main__":
    sys.exit(main())
