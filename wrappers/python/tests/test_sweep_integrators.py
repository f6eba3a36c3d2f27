"""ShardlowIntegrator and LoweAndersenIntegrator from Python: the papers' physics (Nikunen et al.
2003, Fig. 1: Lowe exact at every dt on model A, S1 within 0.5 % up to dt = 0.2), checkpoints,
copies and parameter checks."""
import copy
import math
import pickle

import numpy as np
import openmm
import pytest
from openmm import app, unit

import openmmdpd
from openmmdpd import analysis, scenes

from dpdtest import KT, make_context, momentum, reduced_kT, set_velocities

Shardlow = openmmdpd.ShardlowIntegrator
Lowe = openmmdpd.LoweAndersenIntegrator


def make(scheme, dt, seed=11, gamma=4.5):
    if scheme in ("S1", "S2"):
        integrator = Shardlow(KT, gamma, 1.0, dt)
        integrator.setOrder(1 if scheme == "S1" else 2)
    else:
        integrator = Lowe(KT, gamma, 1.0, dt)
        integrator.setMethod(Lowe.Lowe if scheme == "Lowe" else Lowe.PairOrnsteinUhlenbeck)
    integrator.setRandomNumberSeed(seed)
    return integrator


def sample_kT(scheme, dt, n=2000, samples=1500, scene_name="ideal", gamma=4.5):
    """Block-averaged <kT> over at least 60 time units (kT at small dt is correlated over
    ~1 time unit, so 1500 consecutive steps at dt = 0.01 underestimate its error ~2x)."""
    scene = scenes.build_scene(scene_name, num_particles=n)
    integrator = make(scheme, dt, gamma=gamma)
    context = make_context(scene, integrator, "CPU")
    set_velocities(context, scene.system, 3)
    integrator.step(max(200, int(2 / dt)))
    every = max(1, int(60 / dt) // samples)
    values = []
    for _ in range(samples):
        integrator.step(every)
        values.append(reduced_kT(context, n))
    return analysis.block_average(values, nblocks=10)


@pytest.mark.parametrize("dt", [0.01, 0.1, 0.3])
@pytest.mark.parametrize("scheme", ["Lowe", "PairOU"])
def test_exact_temperature_for_the_ideal_gas_at_any_step(scheme, dt):
    # Gamma = 3 keeps Lowe's collision probability Gamma dt <= 1 at dt = 0.3.
    mean, stderr = sample_kT(scheme, dt, gamma=3.0)
    print(f"\n<kT> ideal {scheme} dt={dt}: {mean:.4f} +- {stderr:.4f}")
    assert 0 < stderr < 0.005
    assert abs(mean - 1) < 3 * stderr + 1e-4


@pytest.mark.parametrize("dt", [0.05, 0.1, 0.2])
def test_shardlow_s1_keeps_the_ideal_gas_within_half_a_percent(dt):
    mean, stderr = sample_kT("S1", dt)
    print(f"\n<kT> ideal S1 dt={dt}: {mean:.4f} +- {stderr:.4f}")
    assert stderr < 0.0025
    assert abs(mean - 1) < 0.005


def test_shardlow_s2_on_soft():
    mean, stderr = sample_kT("S2", 0.04, scene_name="soft")
    print(f"\n<kT> soft S2 dt=0.04: {mean:.4f} +- {stderr:.4f}")
    # S2 is second order in the conservative step: +0.8 % at dt = 0.04 on soft (the
    # committed compare run: 1.0089 +- 0.0015), -- not exact like the ideal gas.
    assert abs(mean - 1) < 0.015


def test_lowe_ideal_gas_radial_distribution_is_flat():
    n, frames, nbins, r_max = 1000, 10, 40, 2.0
    scene = scenes.build_scene("ideal", num_particles=n)
    length = scene.system.getDefaultPeriodicBoxVectors()[0][0].value_in_unit(unit.nanometer)
    integrator = make("Lowe", 0.1)
    context = make_context(scene, integrator, "CPU")
    set_velocities(context, scene.system, 6)
    integrator.step(20)
    g_frames = []
    for _ in range(frames):
        integrator.step(10)
        r, g = analysis.radial_distribution(context.getState(getPositions=True).getPositions(asNumpy=True),
                                            length, r_max, nbins)
        g_frames.append(g)
    g = np.mean(g_frames, axis=0)
    keep = r >= 0.1
    edges = np.linspace(0, r_max, nbins + 1)
    expected_pairs = 0.5 * n * (n - 1) / length ** 3 * 4 / 3 * np.pi * (edges[1:] ** 3 - edges[:-1] ** 3)
    sd = 1 / np.sqrt(expected_pairs * frames)
    chi2 = np.mean(((g[keep] - 1) / sd[keep]) ** 2)
    print(f"\ng(r) ideal Lowe dt=0.1: chi^2/dof = {chi2:.2f}")
    assert chi2 < 2.0


@pytest.mark.parametrize("scheme", ["S1", "S2", "Lowe", "PairOU"])
def test_momentum_is_conserved(scheme):
    scene = scenes.build_scene("soft", num_particles=500)
    integrator = make(scheme, 0.04)
    context = make_context(scene, integrator, "Reference")
    context.setVelocitiesToTemperature(KT, 4)
    before = momentum(context, scene.system)
    integrator.step(30)
    assert np.linalg.norm(before) > 1.0
    assert np.abs(momentum(context, scene.system) - before).max() < 1e-9


@pytest.mark.parametrize("scheme", ["S2", "Lowe"])
def test_simulation_checkpoint_is_bit_exact(tmp_path, scheme):
    scene = scenes.build_scene("soft", num_particles=500)
    simulation = app.Simulation(scene.topology, scene.system, make(scheme, 0.02),
                                openmm.Platform.getPlatformByName("Reference"))
    simulation.context.setPositions(scene.positions)
    simulation.context.setVelocitiesToTemperature(KT, 2)
    simulation.step(10)
    path = str(tmp_path / "run.chk")
    simulation.saveCheckpoint(path)
    simulation.step(10)
    first = simulation.context.getState(getPositions=True, getVelocities=True)
    simulation.loadCheckpoint(path)
    assert simulation.currentStep == 10
    simulation.step(10)
    second = simulation.context.getState(getPositions=True, getVelocities=True)
    assert np.array_equal(first.getPositions(asNumpy=True)._value, second.getPositions(asNumpy=True)._value)
    assert np.array_equal(first.getVelocities(asNumpy=True)._value, second.getVelocities(asNumpy=True)._value)


@pytest.mark.parametrize("scheme", ["S2", "PairOU"])
def test_copies_and_cast_keep_class_and_parameters(scheme):
    original = make(scheme, 0.02, seed=5)
    original.setParticleType(3, 1)
    original.addTypePair(0, 1, 2.5, 0.9)
    xml = openmm.XmlSerializer.serialize(original)
    for other in (copy.deepcopy(original), pickle.loads(pickle.dumps(original)),
                  type(original).cast(openmm.XmlSerializer.deserialize(xml))):
        assert type(other) is type(original)
        assert openmm.XmlSerializer.serialize(other) == xml
    assert (original.getOrder() if scheme == "S2" else original.getMethod()) == (2 if scheme == "S2" else 1)


def test_invalid_parameters_raise():
    with pytest.raises(openmm.OpenMMException, match="order"):
        Shardlow(KT, 4.5, 1.0, 0.01).setOrder(0)
    scene = scenes.build_scene("ideal", num_particles=200)
    with pytest.raises(openmm.OpenMMException, match="Gamma dt"):
        make_context(scene, Lowe(KT, 12 / unit.picosecond, 1.0, 0.1))
    with pytest.raises(TypeError):
        Lowe(KT, 4.5 * unit.nanometer, 1.0, 0.01)
