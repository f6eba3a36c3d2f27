"""Extended DPD's memory, seen in the velocity autocorrelation: scene `soft` with
EDPDIntegrator at alpha = 0.5, 5 and 50 /ps (one-sided scheme) next to DPD-VV with the
same friction (gamma = 4.5).  As alpha grows EDPD approaches DPD; at small alpha the pair
variables act as weak springs between neighbours that relax only at the rate alpha, so
C(t) decays more slowly and D grows.

At small alpha EDPD is also a weak thermostat (heat leaves on ~100 ps at alpha = 0.5), so
every run starts from one configuration equilibrated with DPD-VV, not from the scene's
random positions."""
import argparse

import numpy as np
from openmm import unit

import openmmdpd
from openmmdpd import analysis, catalog, scenes

LAGS = (0.0, 0.05, 0.1, 0.2, 0.3, 0.5, 0.75, 1.0, 1.5, 2.0)  # ps


def integrators(dt, alphas):
    yield "DPD-VV", catalog.integrators()["DPD-VV"](dt)
    for alpha in alphas:
        yield f"EDPD a={alpha:g}", openmmdpd.EDPDIntegrator(openmmdpd.KT_TEMPERATURE, catalog.FRICTION,
                                                             catalog.CUTOFF, alpha, dt)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--particles", type=int, default=2000)
    parser.add_argument("--dt", type=float, default=0.01)
    parser.add_argument("--alphas", type=float, nargs="+", default=[0.5, 5.0, 50.0])
    parser.add_argument("--prepare", type=int, default=2000, help="steps of DPD-VV that equilibrate the one start")
    parser.add_argument("--equilibrate", type=int, default=500, help="steps of each integrator before sampling")
    parser.add_argument("--frames", type=int, default=600, help="velocity frames, one per step")
    parser.add_argument("--platform", default="CPU")
    args = parser.parse_args(argv)

    import openmm
    scene = scenes.build_scene("soft", num_particles=args.particles)
    # One equilibrated start for all: DPD-VV removes the random start's excess heat in ~1 ps.
    warmup = catalog.integrators()["DPD-VV"](args.dt)
    context = openmm.Context(scene.system, warmup, openmm.Platform.getPlatformByName(args.platform))
    context.setPositions(scene.positions)
    context.setVelocitiesToTemperature(openmmdpd.KT_TEMPERATURE, 3)
    warmup.step(args.prepare)
    start = context.getState(getPositions=True, getVelocities=True)
    del context

    lag_frames = [int(round(t / args.dt)) for t in LAGS if t / args.dt < args.frames // 2]
    print(f"soft, N = {args.particles}, dt = {args.dt}: C(t) = <v(0).v(t)>/<v.v>, D = int C dt <v^2>/3")
    print(f"{'':14s}" + "".join(f"{'t=' + format(k * args.dt, 'g'):>8s}" for k in lag_frames)
          + f"{'D':>8s}{'<kT>':>8s}{'s per particle':>16s}")
    for name, integrator in integrators(args.dt, args.alphas):
        integrator.setRandomNumberSeed(7)
        context = openmm.Context(scene.system, integrator, openmm.Platform.getPlatformByName(args.platform))
        context.setPositions(start.getPositions())
        context.setVelocities(start.getVelocities())
        integrator.step(args.equilibrate)
        frames = []
        for _ in range(args.frames):
            integrator.step(1)
            frames.append(context.getState(getVelocities=True).getVelocities(asNumpy=True)
                          .value_in_unit(unit.nanometer / unit.picosecond))
        frames = np.array(frames)
        c = analysis.velocity_autocorrelation(frames, args.frames // 2)
        v2 = float((frames ** 2).sum(axis=2).mean())
        diffusion = np.trapz(c, dx=args.dt) * v2 / 3
        kt = v2 / 3 * len(frames[0]) / (len(frames[0]) - 1)
        stored = (integrator.getNumPairVariables() / args.particles
                  if isinstance(integrator, openmmdpd.EDPDIntegrator) else float("nan"))
        print(f"{name:14s}" + "".join(f"{c[k]:8.3f}" for k in lag_frames)
              + f"{diffusion:8.3f}{kt:8.3f}{stored:16.1f}")


if __name__ == "__main__":
    main()
