"""Scenes, their forces, units and analysis helpers; all on the Reference platform."""
import math

import numpy as np
import openmm
import pytest
from openmm import unit

import openmmdpd
from openmmdpd import analysis, scenes, units


def evaluate(forces, positions, box_length=10.0, platform_name="Reference"):
    """(energy, forces) of `forces` on particles at `positions` (nm) in a periodic box."""
    system = openmm.System()
    for _ in positions:
        system.addParticle(1.0)
    system.setDefaultPeriodicBoxVectors(*(openmm.Vec3(*row) for row in box_length * np.eye(3)))
    for force in forces:
        system.addForce(force)
    context = openmm.Context(system, openmm.VerletIntegrator(0.001),
                             openmm.Platform.getPlatformByName(platform_name))
    context.setPositions(np.asarray(positions, dtype=float))
    state = context.getState(getEnergy=True, getForces=True)
    return (state.getPotentialEnergy().value_in_unit(unit.kilojoule_per_mole),
            state.getForces(asNumpy=True).value_in_unit(unit.kilojoule_per_mole / unit.nanometer))


def pair(r):
    return [[0.0, 0.0, 0.0], [r, 0.0, 0.0]]


def check_radial_force(make_force, r, expected_force, h=1e-5):
    """Force on particle 1 at distance r along x is -dU/dr = expected_force (along +x)."""
    _, f = evaluate([make_force()], pair(r))
    numeric = -(evaluate([make_force()], pair(r + h))[0]
                - evaluate([make_force()], pair(r - h))[0]) / (2 * h)
    assert f[1, 0] == pytest.approx(expected_force, rel=1e-8)
    assert numeric == pytest.approx(expected_force, rel=1e-6)
    assert f[0] == pytest.approx(-f[1])


# --- units -------------------------------------------------------------------------------

def test_kt_one_is_120_kelvin():
    assert units.KT_TEMPERATURE.value_in_unit(unit.kelvin) == pytest.approx(120.27236, abs=1e-5)
    assert units.kT_from_temperature(units.reduced_temperature(2.5)) == pytest.approx(2.5)
    assert units.kT_from_temperature(300.0) == pytest.approx(2.494338785, rel=1e-9)


def test_reduced_temperature_takes_kT_as_an_energy():
    T = units.reduced_temperature(1 * unit.kilojoule_per_mole)
    assert T.unit == unit.kelvin
    assert T.value_in_unit(unit.kelvin) == pytest.approx(120.27236, abs=1e-5)
    assert units.reduced_temperature(4.184 * unit.kilojoule_per_mole).value_in_unit(unit.kelvin) == \
        pytest.approx(units.reduced_temperature(1 * unit.kilocalorie_per_mole).value_in_unit(unit.kelvin))
    for wrong in (300 * unit.kelvin, 1 * unit.nanometer, "1"):
        with pytest.raises(TypeError, match="reduced_temperature: kT must be an energy"):
            units.reduced_temperature(wrong)


def test_strip_units():
    assert units.strip_units(2 * unit.nanometer, unit.angstrom) == pytest.approx(20)
    assert units.strip_units(3, unit.kelvin) == 3.0
    with pytest.raises(TypeError, match="kelvin"):
        units.strip_units(1 * unit.nanometer, unit.kelvin)


# --- scenes ------------------------------------------------------------------------------

@pytest.mark.parametrize("name", [name for name in scenes.SCENES if name != "wlc-shear"])  # cubic ones
def test_scene_size_box_density(name):
    scene = scenes.build_scene(name, num_particles=1000, density=4.0)
    system = scene.system
    assert scene.name == name
    assert system.getNumParticles() == scene.topology.getNumAtoms() == 1000
    assert all(system.getParticleMass(i) == 1.0 * unit.dalton for i in range(1000))
    box = system.getDefaultPeriodicBoxVectors()
    length = box[0][0].value_in_unit(unit.nanometer)
    assert length == pytest.approx((1000 / 4.0) ** (1 / 3))
    assert box[1][1] == box[0][0] == box[2][2] and box[0][1] == 0 * unit.nanometer
    assert system.usesPeriodicBoundaryConditions()
    positions = scene.positions.value_in_unit(unit.nanometer)
    assert positions.shape == (1000, 3)
    solvent = positions[sum(map(len, scene.chain_particles)):]
    assert solvent.min() >= 0 and solvent.max() < length


def test_ideal_scene_has_no_force_but_is_periodic():
    scene = scenes.build_scene("ideal", num_particles=100)
    assert scene.system.usesPeriodicBoundaryConditions()
    energy, forces = evaluate([scenes.periodic_marker_force()], np.zeros((3, 3)))
    assert energy == 0 and not forces.any()


def test_polymer_scene_chain():
    scene = scenes.build_scene("polymer", num_particles=500, chain_length=20, seed=3)
    assert scene.chain_particles == (tuple(range(20)),)
    assert scene.topology.getNumBonds() == 19
    chain = scene.positions.value_in_unit(unit.nanometer)[:20]
    assert np.linalg.norm(np.diff(chain, axis=0), axis=1) == pytest.approx(0.5)
    assert {f.getName() for f in scene.system.getForces()} == {"HarmonicBond", "WCA"}
    # The start is free of WCA overlaps (beads >= 0.9 apart: below 1 kT each).
    wca = scenes.wca_force(20, list(range(20)), zip(range(19), range(1, 20)))
    assert evaluate([wca], chain, box_length=(500 / 4) ** (1 / 3))[0] < 19


def test_polymer_scene_type_matrix_defaults_chain_to_type_1():
    scene = scenes.build_scene("polymer", num_particles=100, a=[[25.0, 30.0], [30.0, 40.0]])
    soft = [f for f in scene.system.getForces() if f.getName() == "SoftRepulsion"][0]
    soft = openmmdpd.DPDSoftRepulsionForce.cast(soft)
    assert [soft.getParticleType(i) for i in range(100)] == [1] * 20 + [0] * 80
    custom = scenes.build_scene("polymer", num_particles=100, a=[[25.0, 30.0], [30.0, 40.0]], native_force=False)
    soft = [f for f in custom.system.getForces() if f.getName() == "SoftRepulsion"][0]
    assert [soft.getParticleParameters(i)[0] for i in range(100)] == [1.0] * 20 + [0.0] * 80


def test_wlc_shear_scene_sizes_and_parameters():
    scene = scenes.build_scene("wlc-shear")
    system = scene.system
    assert scene.name == "wlc-shear" and system.getNumParticles() == scene.topology.getNumAtoms() == 4000
    box = [v.value_in_unit(unit.nanometer) for v in system.getDefaultPeriodicBoxVectors()]
    assert np.allclose(box, np.diag([10.0, 20.0, 5.0]))
    assert scene.chain_particles == ((0, 1, 2, 3, 4),) and scene.topology.getNumBonds() == 4
    forces = {f.getName(): f for f in system.getForces()}
    assert set(forces) == {"WormLikeChain", "SoftRepulsion"}
    soft = openmmdpd.DPDSoftRepulsionForce.cast(forces["SoftRepulsion"])
    assert soft.getDefaultA().value_in_unit(unit.kilojoule_per_mole / unit.nanometer) == pytest.approx(75 / 4)
    assert soft.getForceGroup() == 0
    springs = forces["WormLikeChain"]
    assert springs.getForceGroup() == scenes.FAST_FORCE_GROUP and not springs.usesPeriodicBoundaryConditions()
    assert [springs.getBondParameters(k)[:2] for k in range(4)] == [[0, 1], [1, 2], [2, 3], [3, 4]]
    positions = scene.positions.value_in_unit(unit.nanometer)
    assert positions[5:].min() >= 0 and np.all(positions[5:].max(axis=0) < [10, 20, 5])
    # The start's Underhill-Doyle ratio is that of its extension.
    z = scenes.fractional_extension(positions[:5], 4 * 8.0)
    assert springs.getGlobalParameterDefaultValue(0) == pytest.approx(1 + 0.088 * (1 - z))


def test_underhill_doyle_ratio():
    # Symeonidis and Karniadakis 2006, §3: (1 - z) 0.022 (M - 1) + 1 up to 20 beads, 0.025 beyond;
    # dumbbells uncorrected
    assert scenes.underhill_doyle_ratio(0.0, 5) == pytest.approx(1.088)
    assert scenes.underhill_doyle_ratio(0.5, 5) == pytest.approx(1.044)
    assert scenes.underhill_doyle_ratio(1.0, 5) == 1.0 == scenes.underhill_doyle_ratio(0.3, 2)
    assert scenes.underhill_doyle_ratio(0.0, 20) == pytest.approx(1.418)
    assert scenes.underhill_doyle_ratio(0.0, 21) == pytest.approx(1.5)
    assert scenes.underhill_doyle_ratio(-0.2, 5) == pytest.approx(1.088)


@pytest.mark.parametrize("R", [0.05, 0.3, 0.6, 0.9])
def test_wlc_shear_spring_is_marko_siggia_for_lambda_dna(R):
    """The scene's springs on a straight chain along x, spacing R Lspring: the end bead feels
    kT/(lp lambda) [1/(4(1-R)^2) - 1/4 + R] towards the chain, lp = Lspring 0.053 x 4 / 21.1."""
    scene = scenes.wlc_shear_scene(num_particles=500, box=(10.0, 20.0, 2.5), l_spring=8.0)
    positions = scene.positions.value_in_unit(unit.nanometer)
    chain = np.array([[1.0 + 8.0 * R * k, 10.0, 1.0] for k in range(5)])
    positions[:5] = chain
    context = openmm.Context(scene.system, openmm.VerletIntegrator(0.001), openmm.Platform.getPlatformByName("Reference"))
    context.setPositions(positions)
    ratio = scenes.update_persistence_ratio(context, chain, 32.0)
    assert ratio == pytest.approx(1 + 0.088 * (1 - R)) and context.getParameter(scenes.WLC_LP_RATIO) == ratio
    f = context.getState(getForces=True, groups={scenes.FAST_FORCE_GROUP}).getForces(asNumpy=True)
    f = f.value_in_unit(unit.kilojoule_per_mole / unit.nanometer)
    lp = 8.0 * 0.053 * 4 / 21.1
    expected = 1.0 / (lp * ratio) * (1 / (4 * (1 - R) ** 2) - 0.25 + R)
    assert f[0] == pytest.approx([expected, 0, 0], rel=1e-9, abs=1e-9)
    assert f[2] == pytest.approx([0, 0, 0], abs=1e-9 * expected)
    assert f[5:] == pytest.approx(np.zeros((495, 3)))


def test_seed_reproducible():
    a = scenes.build_scene("soft", num_particles=100, seed=7).positions
    b = scenes.build_scene("soft", num_particles=100, seed=7).positions
    c = scenes.build_scene("soft", num_particles=100, seed=8).positions
    assert np.array_equal(a, b) and not np.array_equal(a, c)


def test_unknown_scene():
    with pytest.raises(ValueError, match="unknown scene"):
        scenes.build_scene("nope")


# --- forces ------------------------------------------------------------------------------

@pytest.mark.parametrize("native", [True, False])
@pytest.mark.parametrize("r", [0.0001, 0.3, 0.75, 0.999])
def test_soft_repulsion_energy_and_force(r, native):
    energy, forces = evaluate([scenes.soft_repulsion_force(2, 25.0, native=native)], pair(r))
    assert energy == pytest.approx(25.0 * (1 - r) ** 2 / 2)
    assert forces[1, 0] == pytest.approx(25.0 * (1 - r))


@pytest.mark.parametrize("native", [True, False])
def test_soft_repulsion_zero_beyond_cutoff_and_across_boundary(native):
    assert evaluate([scenes.soft_repulsion_force(2, 25.0, native=native)], pair(1.2))[0] == 0
    # 9.5 apart in a box of 10 is 0.5 apart through the boundary.
    energy, _ = evaluate([scenes.soft_repulsion_force(2, 25.0, native=native)], pair(9.5))
    assert energy == pytest.approx(25.0 * 0.5 ** 2 / 2)


@pytest.mark.parametrize("native", [True, False])
def test_soft_repulsion_type_matrix(native):
    a = [[25.0, 40.0], [40.0, 10.0]]
    for types, a_ij in [((0, 1), 40.0), ((1, 0), 40.0), ((1, 1), 10.0), ((0, 0), 25.0)]:
        energy, _ = evaluate([scenes.soft_repulsion_force(2, a, types, native=native)], pair(0.4))
        assert energy == pytest.approx(a_ij * 0.6 ** 2 / 2)
    with pytest.raises(ValueError):
        scenes.soft_repulsion_force(2, [[1.0, 2.0], [3.0, 4.0]], (0, 1))


def test_harmonic_bond():
    energy, forces = evaluate([scenes.harmonic_bond_force([(0, 1)])], pair(0.8))
    assert energy == pytest.approx(7 * 0.8 ** 2 / 2)
    assert forces[1, 0] == pytest.approx(-7 * 0.8)


@pytest.mark.parametrize("r", [0.5, 1.0, 2.5, 2.99])
def test_fene_force_below_rmax(r):
    expected = -7.0 * r / (1 - (r / 3.0) ** 2)
    check_radial_force(lambda: scenes.fene_bond_force([(0, 1)]), r, expected)
    energy, _ = evaluate([scenes.fene_bond_force([(0, 1)])], pair(r))
    assert energy == pytest.approx(-0.5 * 7 * 9 * math.log(1 - r * r / 9))


@pytest.mark.parametrize("platform_name", ["Reference", "CPU"])
def test_fene_is_nan_past_rmax(platform_name):
    energy, forces = evaluate([scenes.fene_bond_force([(0, 1)])], pair(3.5),
                              platform_name=platform_name)
    assert math.isnan(energy) and np.isnan(forces).all()


@pytest.mark.parametrize("r", [0.1, 0.8, 1.5, 1.95])
def test_wlc_force_matches_marko_siggia(r):
    lp, l_spring, kT = 0.4, 2.0, 1.3
    R = r / l_spring
    expected = -kT / lp * (1 / (4 * (1 - R) ** 2) - 0.25 + R)  # restoring: along -x on 1
    check_radial_force(lambda: scenes.wlc_bond_force([(0, 1)], lp, l_spring, kT), r, expected)


@pytest.mark.parametrize("platform_name", ["Reference", "CPU"])
def test_wlc_energy_zero_at_contact_and_nan_past_full_extension(platform_name):
    force = lambda: scenes.wlc_bond_force([(0, 1)], 0.5, 2.0)  # noqa: E731
    assert evaluate([force()], pair(0.0))[0] == pytest.approx(0, abs=1e-12)
    energy, forces = evaluate([force()], pair(2.5), platform_name=platform_name)
    assert math.isnan(energy) and np.isnan(forces).all()


def test_wca_acts_only_between_unbonded_chain_beads():
    # Chain 0-1-2 (bonds excluded), solvent 3 close to every bead.
    positions = [[0, 0, 0], [0.45, 0.3, 0], [0.9, 0, 0], [0.2, -0.3, 0]]
    force = scenes.wca_force(4, [0, 1, 2], [(0, 1), (1, 2)])
    energy, forces = evaluate([force], positions)
    x = 2 ** (-1 / 6) / 0.9
    assert energy == pytest.approx(4 * (x ** 12 - x ** 6 + 0.25))
    assert not forces[[1, 3]].any()
    assert forces[2, 0] > 0 and forces[0] == pytest.approx(-forces[2])


def test_wca_vanishes_at_cutoff():
    force = lambda: scenes.wca_force(2, [0, 1])  # noqa: E731
    assert evaluate([force()], pair(0.99999))[0] == pytest.approx(0, abs=1e-8)
    assert evaluate([force()], pair(2 ** (-1 / 6)))[0] == pytest.approx(1.0)


# --- analysis ----------------------------------------------------------------------------

def test_kinetic_temperature():
    rng = np.random.default_rng(0)
    masses = np.full(3000, 2.0)
    velocities = rng.normal(scale=np.sqrt(1.5 / 2.0), size=(3000, 3))
    assert analysis.kinetic_temperature(velocities, masses) == pytest.approx(1.5, rel=0.02)
    exact = np.sum(masses[:, None] * velocities ** 2) / (3 * 3000 - 3)
    quantities = [m * unit.dalton for m in masses]
    assert analysis.kinetic_temperature(velocities * unit.nanometer / unit.picosecond,
                                        quantities) == pytest.approx(exact)


def test_block_average_known_data():
    mean, error = analysis.block_average(np.repeat([1.0, 2.0, 3.0, 4.0], 5), nblocks=4)
    assert mean == pytest.approx(2.5)
    assert error == pytest.approx(np.std([1, 2, 3, 4], ddof=1) / 2)
    mean, error = analysis.block_average(np.arange(23.0), nblocks=2)  # trailing 3 dropped
    assert mean == pytest.approx(10.5) and error == pytest.approx(5.5)


def test_radial_distribution_of_uniform_points_is_one():
    rng = np.random.default_rng(2)
    length = 10.0
    positions = rng.uniform(0, length, size=(4000, 3))
    r, g = analysis.radial_distribution(positions, length * unit.nanometer, 3.0, 30)
    assert r == pytest.approx(np.arange(0.05, 3.0, 0.1))
    assert g.mean() == pytest.approx(1.0, abs=0.01)
    shell = 4 / 3 * np.pi * ((r + 0.05) ** 3 - (r - 0.05) ** 3)
    sigma = 1 / np.sqrt(0.5 * 4000 * 3999 / length ** 3 * shell)  # Poisson error per bin
    assert np.all(np.abs(g - 1) < 5 * sigma)


def test_radial_distribution_counts_pairs_through_the_boundary():
    r, g = analysis.radial_distribution([[0.1, 5, 5], [9.85, 5, 5]], 10.0, 1.0, 10)
    assert np.argmax(g) == 2 and np.count_nonzero(g) == 1


def test_radius_of_gyration():
    chain = np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0]], dtype=float)
    assert analysis.radius_of_gyration(chain) == pytest.approx(np.sqrt(2 / 3))
    assert analysis.radius_of_gyration(chain * unit.nanometer + 5 * unit.nanometer) == \
        pytest.approx(np.sqrt(2 / 3))


def test_velocity_autocorrelation_of_an_ar1_process_decays_geometrically():
    # v(t) = phi v(t-1) + noise has C(k) = phi^k exactly in expectation.
    rng = np.random.default_rng(4)
    phi, frames = 0.8, 400
    v = np.empty((frames, 300, 3))
    v[0] = rng.normal(size=(300, 3))
    for t in range(1, frames):
        v[t] = phi * v[t - 1] + np.sqrt(1 - phi ** 2) * rng.normal(size=(300, 3))
    c = analysis.velocity_autocorrelation(v, 10)
    assert c[0] == pytest.approx(1.0)
    assert np.allclose(c, phi ** np.arange(11), atol=0.01)
    with pytest.raises(ValueError):
        analysis.velocity_autocorrelation(v, frames)
