"""Runs of the time-staggered integrator on the `fene-chains` scene (Symeonidis and Karniadakis 2006, §5).

Everything in reduced units (see units.py). `run_fene_chains` is what the benchmark
(`python3 -m openmmdpd.bench staggered`) and the statistical tests share: it times the
integration at equal simulated time and measures the chain and total <kT> and <Rg>.
"""
import time

import numpy as np
import openmm

from . import StaggeredDPDIntegrator
from .analysis import block_average
from .scenes import fene_chains_scene
from .units import KT_TEMPERATURE

__all__ = ["staggered_integrator", "equilibrated_fene_chains", "run_fene_chains"]

FRICTION = 4.5  # gamma (vV base) or Lowe's Gamma, 1/ps
CUTOFF = 1.0


def staggered_integrator(num_sub_steps, inner_dt, base="vv", weighted=True, relaxation=None, lam=None, seed=1):
    """StaggeredDPDIntegrator with outer step Dt = K dt and Symeonidis and Karniadakis'
    recommended parameters for the base ("vv" or "lowe") unless relaxation=(mu, a, b) / lam are given."""
    integrator = StaggeredDPDIntegrator(KT_TEMPERATURE, FRICTION, CUTOFF, num_sub_steps * inner_dt, num_sub_steps)
    integrator.setBaseScheme(StaggeredDPDIntegrator.LoweAndersen if base == "lowe" else StaggeredDPDIntegrator.VelocityVerlet)
    integrator.useRecommendedParameters()
    integrator.setWeighted(weighted)
    if relaxation is not None:
        integrator.setRelaxationParameters(*relaxation)
    if lam is not None:
        integrator.setLambda(lam)
    integrator.setRandomNumberSeed(seed)
    return integrator


def _context(scene, integrator, platform, threads):
    properties = {"Threads": str(threads)} if platform == "CPU" else {}
    return openmm.Context(scene.system, integrator, openmm.Platform.getPlatformByName(platform), properties)


def equilibrated_fene_chains(chain_length=20, num_chains=4, num_particles=4000, time_units=5.0, platform="CPU",
                             threads=1, seed=1):
    """(scene, state): the scene after `time_units` of staggered vV (dt = 0.002, K = 5),
    long enough for the soft fluid and the chains' bonds to relax from the random start."""
    scene = fene_chains_scene(chain_length=chain_length, num_chains=num_chains, num_particles=num_particles, seed=seed)
    integrator = staggered_integrator(5, 0.002, seed=seed + 1000)
    context = _context(scene, integrator, platform, threads)
    context.setPositions(scene.positions)
    context.setVelocitiesToTemperature(KT_TEMPERATURE, seed)
    integrator.step(round(time_units / 0.01))  # Dt = 5 x 0.002
    return scene, context.getState(getPositions=True, getVelocities=True)


def run_fene_chains(scene, state, num_sub_steps, inner_dt, sample_time, base="vv", weighted=True, relaxation=None,
                    sample_interval=0.05, equilibration_time=1.0, rg=False, platform="CPU", threads=1, seed=1):
    """Run the staggered integrator from `state` and measure it.

    Returns a dict: seconds (wall time of the sampled run's steps alone), simulated_time,
    seconds_per_time (wall time per unit of simulated time), chain_kT and total_kT
    ((mean, standard error) from 10 block averages; kT = sum m v^2 / (3N - 3) over all
    particles, and m v^2 / 3 per bead over the chain beads, Symeonidis and Karniadakis 2006, §5.1), and with
    rg=True, rg ((mean, standard error) of the chains' radius of gyration).
    """
    integrator = staggered_integrator(num_sub_steps, inner_dt, base, weighted, relaxation, seed=seed)
    context = _context(scene, integrator, platform, threads)
    context.setState(state)
    context.setStepCount(0)
    outer = num_sub_steps * inner_dt
    if equilibration_time > 0:
        integrator.step(max(1, round(equilibration_time / outer)))
    chains = [list(chain) for chain in scene.chain_particles]
    beads = [i for chain in chains for i in chain]
    n = scene.system.getNumParticles()
    masses = np.array([scene.system.getParticleMass(i).value_in_unit(openmm.unit.dalton) for i in range(n)])
    every = max(1, round(sample_interval / outer))
    num_samples = max(10, round(sample_time / (every * outer)))
    chain_kT, total_kT, radii = [], [], []
    seconds = 0.0
    for _ in range(num_samples):
        start = time.perf_counter()
        integrator.step(every)
        seconds += time.perf_counter() - start
        current = context.getState(getVelocities=True, getPositions=rg)
        v = current.getVelocities(asNumpy=True).value_in_unit(openmm.unit.nanometer / openmm.unit.picosecond)
        mv2 = masses[:, None] * v * v
        chain_kT.append(mv2[beads].sum() / (3 * len(beads)))
        p = (masses[:, None] * v).sum(axis=0)
        total_kT.append((mv2.sum() - p.dot(p) / masses.sum()) / (3 * n - 3))
        if rg:
            x = current.getPositions(asNumpy=True).value_in_unit(openmm.unit.nanometer)
            for chain in chains:
                c = x[chain]
                radii.append(np.sqrt(np.mean(np.sum((c - c.mean(axis=0)) ** 2, axis=1))))
    simulated = num_samples * every * outer
    result = {"seconds": seconds, "simulated_time": simulated, "seconds_per_time": seconds / simulated,
              "chain_kT": block_average(chain_kT), "total_kT": block_average(total_kT)}
    if rg:
        # one value per sample: the mean over the chains
        per_sample = np.asarray(radii).reshape(num_samples, len(chains)).mean(axis=1)
        result["rg"] = block_average(per_sample)
    return result


if __name__ == "__main__":
    from .options import not_a_command
    not_a_command("staggered",
                  "Its runs of StaggeredDPDIntegrator on the fene-chains scene are timed by `python3 -m openmmdpd.bench"
                  " staggered` (about a minute; see its --help), and called from Python as "
                  "openmmdpd.staggered.run_fene_chains.")
