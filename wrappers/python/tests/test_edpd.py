"""EDPDIntegrator from Python: the DPD limit against DPDVVIntegrator, <kT> at finite alpha
(Cotter and Reich 2003), the symmetric scheme's failure far beyond alpha dt = 1, units and copies."""
import copy
import pickle

import numpy as np
import openmm
import pytest
from openmm import unit

import openmmdpd
from openmmdpd import analysis, scenes

from dpdtest import KT, make_context, momentum, set_velocities

EDPD = openmmdpd.EDPDIntegrator


def make(alpha, dt, scheme=EDPD.OneSided, seed=11, friction=4.5):
    integrator = EDPD(KT, friction, 1.0, alpha, dt)
    integrator.setScheme(scheme)
    integrator.setRandomNumberSeed(seed)
    return integrator


def sample(integrator, scene, seed, steps, every=20, lag_steps=100):
    """(kT samples, per-particle D from the mean square displacement over lag_steps)."""
    context = make_context(scene, integrator, "CPU")
    set_velocities(context, scene.system, seed)
    integrator.step(200)
    n = scene.system.getNumParticles()
    kts, positions = [], []
    for _ in range(steps // every):
        integrator.step(every)
        state = context.getState(getPositions=True, getVelocities=True)
        v = state.getVelocities(asNumpy=True).value_in_unit(unit.nanometer / unit.picosecond)
        kts.append(float((v * v).sum() / (3 * n - 3)))
        positions.append(state.getPositions(asNumpy=True).value_in_unit(unit.nanometer))
    positions = np.array(positions)
    lag = lag_steps // every
    msd = ((positions[lag:] - positions[:-lag]) ** 2).sum(axis=-1).mean(axis=0)
    tau = lag_steps * integrator.getStepSize().value_in_unit(unit.picosecond)
    return np.array(kts), msd / (6 * tau)


def test_units_copies_and_xml():
    integrator = EDPD(120.27 * unit.kelvin, 4.5 / unit.picosecond, 1.0 * unit.nanometer,
                      5.0 / unit.picosecond, 10 * unit.femtosecond)
    integrator.setScheme(EDPD.Symmetric)
    integrator.setRandomNumberSeed(3)
    assert integrator.getAlpha() == 5.0 / unit.picosecond
    assert integrator.getStepSize().value_in_unit(unit.picosecond) == pytest.approx(0.01)
    integrator.setAlpha(2.5 / unit.picosecond)
    for other in (pickle.loads(pickle.dumps(integrator)), copy.deepcopy(integrator),
                  EDPD.cast(openmm.XmlSerializer.deserialize(openmm.XmlSerializer.serialize(integrator)))):
        assert isinstance(other, EDPD)
        assert other.getAlpha() == 2.5 / unit.picosecond
        assert other.getScheme() == EDPD.Symmetric
        assert other.getRandomNumberSeed() == 3
    with pytest.raises(openmm.OpenMMException, match="alpha"):
        integrator.setAlpha(-1)


def test_pair_variables_are_readable_with_units():
    scene = scenes.build_scene("soft", num_particles=500)
    integrator = make(5.0, 0.02)
    context = make_context(scene, integrator)
    set_velocities(context, scene.system, 1)
    p0 = momentum(context, scene.system)
    integrator.step(20)
    assert np.abs(momentum(context, scene.system) - p0).max() < 1e-10
    assert integrator.getNumPairVariables() > 500
    values = [integrator.getPairVariable(0, j) for j in range(1, 500)]
    known = [v.value_in_unit(unit.kilojoule_per_mole / unit.nanometer) for v in values]
    known = [v for v in known if not np.isnan(v)]
    assert len(known) > 5


def test_dpd_limit_matches_dpd_vv_on_the_ideal_gas():
    """alpha dt = 100 with friction fixed (lambda = alpha gamma): the one-sided scheme is the
    DPD fluid DPDVVIntegrator simulates, in <kT> and in the diffusion coefficient."""
    scene = scenes.build_scene("ideal", num_particles=1000)
    dt, steps = 0.01, 3000
    results = {}
    for name, integrator in (("DPD-VV", openmmdpd.DPDVVIntegrator(KT, 4.5, 1.0, dt)),
                             ("EDPD", make(1e4, dt))):
        integrator.setRandomNumberSeed(5)
        kts, d = sample(integrator, scene, 3, steps)
        kt, kt_err = analysis.block_average(kts, 10)
        results[name] = (kt, kt_err, d.mean(), d.std() / np.sqrt(len(d)))
        print(f"\n{name}: <kT> {kt:.4f} +- {kt_err:.4f}, D {d.mean():.4f} +- {results[name][3]:.4f}")
    (kt1, e1, d1, de1), (kt2, e2, d2, de2) = results["DPD-VV"], results["EDPD"]
    assert abs(kt1 - kt2) < 4 * np.hypot(e1, e2) + 0.002
    assert de1 < 0.01 * d1 and de2 < 0.01 * d2
    assert abs(d1 - d2) < 4 * np.hypot(de1, de2)


def test_symmetric_scheme_fails_far_beyond_alpha_dt_of_one():
    """docs/theory/edpd.md: the symmetric recurrence is unstable for alpha dt >> 1 (here 100),
    where the one-sided one is the DPD limit (previous test)."""
    scene = scenes.build_scene("ideal", num_particles=1000)
    integrator = make(1e4, 0.01, EDPD.Symmetric)
    try:
        kts, _ = sample(integrator, scene, 3, 400)
    except openmm.OpenMMException as error:
        assert "blew up" in str(error)
        return
    assert kts.mean() > 1.5


def replica_kT(alpha, scheme, replicas, steps):
    scene = scenes.build_scene("ideal", num_particles=1000)
    means = []
    for replica in range(replicas):
        kts, _ = sample(make(alpha, 0.01, scheme, seed=100 + replica), scene, replica, steps, every=10)
        means.append(kts.mean())
    mean, stderr = np.mean(means), np.std(means, ddof=1) / np.sqrt(replicas)
    print(f"\n<kT> ideal EDPD alpha={alpha} scheme={scheme}: {mean:.4f} +- {stderr:.4f} ({replicas} x {steps} steps)")
    return mean, stderr


@pytest.mark.parametrize("scheme", [EDPD.OneSided, EDPD.Symmetric])
def test_finite_alpha_keeps_kT(scheme):
    """<kT> = 1 within statistics at dt = 0.01 and alpha = 10; the error comes from the
    scatter of independent replicas, since the pair variables store energy that exchanges
    with the particles on the memory time 1/alpha."""
    mean, stderr = replica_kT(10.0, scheme, 3, 800)
    assert stderr < 0.006
    assert abs(mean - 1) < 4 * stderr + 0.002


@pytest.mark.slow
@pytest.mark.parametrize("scheme", [EDPD.OneSided, EDPD.Symmetric])
def test_long_memory_keeps_kT(scheme):
    """alpha = 1: a memory of 100 steps, and 5-ps swings of +-3 % in the particles' share
    of the energy, so 8 replicas of 60 ps (one replica's mean scatters by ~1.2 %)."""
    mean, stderr = replica_kT(1.0, scheme, 8, 6000)
    assert stderr < 0.008
    assert abs(mean - 1) < 4 * stderr + 0.002
