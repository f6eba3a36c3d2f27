"""The instability sentinel (setInstabilityThreshold) on the polymer scene's transient blow-ups
at dt = 0.03 (issue 13), and its silence on a normal run."""
import numpy as np
import openmm
import pytest

from dpdtest import make_context, set_velocities
from openmmdpd import scenes
from openmmdpd.catalog import INSTABILITY_THRESHOLD, integrators

# Seeds (scene, thermostat and velocities) whose run at dt = 0.03 on the CPU platform (one
# thread) goes through a WCA collision that throws a chain bead out at tens of kT, found by
# running 5000 steps with the sentinel on for seeds 1-22 (GW and S1: 9 of 44 runs fired; without
# it one went on to blow up, the others recovered).  S1's seed was found again when its update
# became one kick, which moved its trajectories by rounding (3 of its 22 runs fire now):
# S1, seed 19: bead 8 at 59 kT at step 3780; the chain's kT peaks at 4.5 over the next 10 steps.
# GW, seed 13: bead 16 at 53 kT at step 864; the chain's kT peaks at 4.3.
# A trajectory this chaotic depends on the last bit of the arithmetic: another build or CPU
# may need other seeds.
EVENTS = [("S1", 19, 3780, 8, 4.0), ("GW", 13, 864, 16, 4.0)]


def _polymer_run(name, seed, threshold):
    scene = scenes.polymer_scene(num_particles=500, seed=seed)
    integrator = integrators()[name](0.03)
    integrator.setRandomNumberSeed(seed)
    integrator.setInstabilityThreshold(threshold)
    context = make_context(scene, integrator, "CPU")
    set_velocities(context, scene.system, seed)
    return integrator, context, np.array(scene.chain_particles[0])


def _kinetic_energies(context):
    v = context.getState(getVelocities=True).getVelocities(asNumpy=True)._value
    return 0.5 * (v * v).sum(axis=1)  # unit masses, kJ/mol = kT


@pytest.mark.parametrize("name, seed, step, particle, chain_kT", EVENTS)
def test_sentinel_stops_the_polymer_event_that_passes_silently_without_it(name, seed, step, particle, chain_kT):
    integrator, context, _ = _polymer_run(name, seed, INSTABILITY_THRESHOLD)
    with pytest.raises(openmm.OpenMMException, match=f"unstable at step {step}: particle {particle} has kinetic energy"):
        integrator.step(step + 100)
    # The same run without the sentinel: the event happens, nothing is reported, the run goes on.
    integrator, context, chain = _polymer_run(name, seed, 0)
    integrator.step(step - 1)
    assert _kinetic_energies(context).max() < INSTABILITY_THRESHOLD
    peak = 0
    for k in range(10):
        integrator.step(1)
        energies = _kinetic_energies(context)
        if k == 0:
            assert energies.argmax() == particle and energies.max() > INSTABILITY_THRESHOLD
        peak = max(peak, 2 * energies[chain].sum() / (3 * len(chain)))
    assert particle in chain and peak > chain_kT
    integrator.step(100)
    assert context.getState().getStepCount() == step + 109


def test_sentinel_is_silent_on_a_normal_run():
    # Model B at dt = 0.04, 2 x 4000 steps of 500 particles: a thermal particle passes 40 kT
    # with probability ~3e-17 per step, so nothing may stop this.
    scene = scenes.soft_scene(num_particles=500, seed=3)
    for name in ("GW", "S1"):
        integrator = integrators()[name](0.04)
        integrator.setRandomNumberSeed(3)
        integrator.setInstabilityThreshold(INSTABILITY_THRESHOLD)
        context = make_context(scene, integrator, "CPU")
        set_velocities(context, scene.system, 3)
        integrator.step(4000)
        assert _kinetic_energies(context).max() < INSTABILITY_THRESHOLD


def test_threshold_is_a_plain_number_checked_on_input():
    integrator = integrators()["GW"](0.01)
    assert integrator.getInstabilityThreshold() == 0
    integrator.setInstabilityThreshold(40)
    assert integrator.getInstabilityThreshold() == 40
    with pytest.raises(openmm.OpenMMException, match="instabilityThreshold must be >= 0"):
        integrator.setInstabilityThreshold(-1)
    assert integrator.getInstabilityThreshold() == 40
