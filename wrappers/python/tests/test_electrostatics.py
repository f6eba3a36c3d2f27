"""Smeared-charge electrostatics (openmmdpd.electrostatics): the pair energies against the
Coulomb energy of the charge clouds, the System's energies and forces (PME plus the smearing
correction) against an Ewald sum written here in numpy, the limits of two charges' energy,
exclusions, the Bjerrum length in other units, and the errors; Reference and CPU platforms."""
import math

import numpy as np
import openmm
import pytest
from openmm import unit
from scipy import integrate, special

import openmmdpd
from openmmdpd import electrostatics
from openmmdpd.electrostatics import add_smeared_electrostatics, smeared_pair_energy, smeared_pair_limit

PLATFORMS = ["Reference", "CPU"]
FORMS = ["slater", "slater-overlap", "gaussian"]
# Lengths whose correction (tolerance 1e-6 kT) fits the test box.
LENGTHS = {"slater": 0.3, "slater-overlap": 0.25, "gaussian": 0.25}
BJERRUM = 1.1
EDGE = 6.0
KJ = unit.kilojoule_per_mole
NM = unit.nanometer


# --- The charge clouds ------------------------------------------------------------------------

def cloud_transforms(form, length):
    """The Fourier transforms of the two clouds of unit charge whose energy `form` is."""
    exponential = lambda k: 1 / (1 + (k * length / 2) ** 2) ** 2  # exp(-2r/length) / (pi length^3)
    gaussian = lambda k: np.exp(-(k * length) ** 2 / 2)  # standard deviation `length`
    point = lambda k: 1.0
    return {"slater": (point, exponential), "slater-overlap": (exponential, exponential),
            "gaussian": (gaussian, gaussian)}[form]


def cloud_energy(r, form, length):
    """Coulomb energy (l_B = 1) of the two clouds at distance r, from their transforms:
    U = (2/pi) int_0^inf rho_a(k) rho_b(k) sin(kr)/(kr) dk (the sine factor is 1 at r = 0)."""
    a, b = cloud_transforms(form, length)
    if r == 0:
        return 2 / np.pi * integrate.quad(lambda k: a(k) * b(k), 0, np.inf, epsabs=1e-13)[0]
    near = integrate.quad(lambda k: a(k) * b(k) * np.sinc(k * r / np.pi), 0, 20, limit=400, epsabs=1e-13)[0]
    far = integrate.quad(lambda k: a(k) * b(k) / (k * r), 20, np.inf, weight="sin", wvar=r, epsabs=1e-13)[0]
    return 2 / np.pi * (near + far)


@pytest.mark.parametrize("form", FORMS)
def test_the_pair_energy_is_the_coulomb_energy_of_the_clouds(form):
    length = 0.4
    for r in (0.02, 0.3, 0.8, 2.0):
        assert smeared_pair_energy(r, form, length) == pytest.approx(cloud_energy(r, form, length), rel=1e-7)
    assert smeared_pair_energy(0.0, form, length) == pytest.approx(cloud_energy(0.0, form, length), rel=1e-7)
    assert smeared_pair_limit(form, length, 2.0) == pytest.approx(2 * cloud_energy(0.0, form, length), rel=1e-7)


# --- An Ewald sum of smeared charges ----------------------------------------------------------

def pair_shape(d, form, length):
    """u_smeared(d) - 1/d for l_B = 1, and its derivative (central difference)."""
    h = 1e-6
    shape = lambda x: smeared_pair_energy(x, form, length) - 1 / x
    return shape(d), (shape(d + h) - shape(d - h)) / (2 * h)


def ewald(x, z, edge, form, length, excluded=(), alpha=1.6, images=2):
    """Energy (kT) and forces (kT/r_c) of periodic smeared charges z at x (l_B = BJERRUM): point
    charges by Ewald (erfc splitting, reciprocal sum over k), plus u_smeared - u_point summed
    directly over every pair and image; an excluded pair has neither its point nor its smeared
    interaction (its images keep theirs)."""
    n = len(z)
    zz = np.outer(z, z)
    drop = np.zeros((n, n), dtype=bool)
    for i, j in excluded:
        drop[i, j] = drop[j, i] = True
    energy, forces = 0.0, np.zeros((n, 3))
    shifts = np.array([(a, b, c) for a in range(-images, images + 1) for b in range(-images, images + 1)
                       for c in range(-images, images + 1)], dtype=float) * edge
    delta = x[:, None, :] - x[None, :, :]
    for shift in shifts:
        vec = delta + shift
        d = np.linalg.norm(vec, axis=-1)
        keep = d > 0  # a particle with itself, unshifted
        direct = keep & ~(drop & (np.abs(shift).sum() == 0))
        dd = np.where(keep, d, 1.0)
        phi = special.erfc(alpha * dd) / dd
        slope = -phi / dd - 2 * alpha / np.sqrt(np.pi) * np.exp(-(alpha * dd) ** 2) / dd
        near = direct & (d < 20 * length)  # beyond, the clouds' overlap is below 1e-17
        shape = np.zeros((n, n)), np.zeros((n, n))
        if near.any():
            values, slopes = pair_shape(d[near], form, length)
            shape[0][near], shape[1][near] = values, slopes
        # an excluded pair: erfc/d - 1/d cancels the reciprocal sum's part of it
        cut = keep & ~direct
        phi, slope = phi - np.where(cut, 1 / dd, 0.0), slope + np.where(cut, 1 / dd ** 2, 0.0)
        total, total_slope = np.where(keep, phi, 0.0) + shape[0], np.where(keep, slope, 0.0) + shape[1]
        energy += 0.5 * np.sum(zz * total)
        forces -= np.sum((zz * total_slope / dd)[:, :, None] * vec, axis=1)
    recip_energy, recip_forces = reciprocal(x, z, edge, alpha)
    energy += recip_energy - alpha / np.sqrt(np.pi) * np.sum(z ** 2)
    return BJERRUM * energy, BJERRUM * (forces + recip_forces)


def reciprocal(x, z, edge, alpha, kmax=14):
    m = np.arange(-kmax, kmax + 1)
    k = 2 * np.pi / edge * np.array(np.meshgrid(m, m, m, indexing="ij")).reshape(3, -1).T
    k = k[np.any(k != 0, axis=1)]
    k2 = np.sum(k ** 2, axis=1)
    weight = np.exp(-k2 / (4 * alpha ** 2)) / k2
    phase = np.exp(1j * x @ k.T)  # (n, nk)
    structure = phase.T @ z
    volume = edge ** 3
    energy = 2 * np.pi / volume * np.sum(weight * np.abs(structure) ** 2)
    forces = 4 * np.pi / volume * z[:, None] * (np.imag(np.conj(structure)[None, :] * phase) * weight) @ k
    return energy, forces


def test_the_numpy_ewald_forces_are_its_energy_gradient():
    x, z = configuration(8, seed=3)
    form, length = "slater", LENGTHS["slater"]
    energy, forces = ewald(x, z, EDGE, form, length, excluded=[(0, 1)])
    h = 1e-5
    for i, axis in ((0, 0), (3, 2)):
        step = np.zeros_like(x)
        step[i, axis] = h
        up = ewald(x + step, z, EDGE, form, length, excluded=[(0, 1)])[0]
        down = ewald(x - step, z, EDGE, form, length, excluded=[(0, 1)])[0]
        assert forces[i, axis] == pytest.approx(-(up - down) / (2 * h), rel=1e-6, abs=1e-8)
    # the splitting parameter is a choice: the sum does not depend on it
    assert ewald(x, z, EDGE, form, length, alpha=1.2)[0] == pytest.approx(ewald(x, z, EDGE, form, length)[0], rel=1e-9)


# --- Systems ----------------------------------------------------------------------------------

def configuration(n, seed, min_distance=0.15):
    """n beads at random in the box (no two closer than min_distance), valences +1, -1, +2, 0, -1, -1
    repeated (neutral for n a multiple of 6)."""
    rng = np.random.default_rng(seed)
    x = []
    while len(x) < n:
        trial = rng.uniform(0, EDGE, 3)
        if all(np.linalg.norm((trial - p + EDGE / 2) % EDGE - EDGE / 2) > min_distance for p in x):
            x.append(trial)
    z = np.resize([1.0, -1.0, 2.0, 0.0, -1.0, -1.0], n)
    return np.array(x), z


def periodic_system(n, edge=EDGE, r_c=1.0):
    system = openmm.System()
    for _ in range(n):
        system.addParticle(1.0)
    system.setDefaultPeriodicBoxVectors(*(openmm.Vec3(*row) * edge * r_c for row in np.eye(3)))
    return system


def evaluate(system, x, platform, r_c=1.0, kT=1.0):
    """Energy (kT) and forces (kT/r_c) of `system` at reduced positions x."""
    properties = {"Threads": "1"} if platform == "CPU" else {}
    context = openmm.Context(system, openmm.VerletIntegrator(0.001), openmm.Platform.getPlatformByName(platform),
                             properties)
    context.setPositions(x * r_c)
    state = context.getState(getEnergy=True, getForces=True)
    energy = state.getPotentialEnergy().value_in_unit(KJ) / kT
    forces = state.getForces(asNumpy=True).value_in_unit(KJ / NM) * r_c / kT
    return energy, forces


def smeared_system(x, z, form, excluded=(), **kwargs):
    system = periodic_system(len(z))
    added = add_smeared_electrostatics(system, z, BJERRUM, LENGTHS[form], form, exclusions=excluded,
                                       tolerance=1e-6, ewald_tolerance=1e-6, **kwargs)
    return system, added


def assert_close(actual, expected, rel=1e-5):
    energy, forces = actual
    energy_ref, forces_ref = expected
    assert energy == pytest.approx(energy_ref, rel=rel)
    assert np.linalg.norm(forces - forces_ref) <= rel * np.linalg.norm(forces_ref)


@pytest.mark.parametrize("platform", PLATFORMS)
@pytest.mark.parametrize("form", FORMS)
def test_energy_and_forces_match_an_ewald_sum(form, platform):
    x, z = configuration(24, seed=11)
    system, _ = smeared_system(x, z, form)
    assert_close(evaluate(system, x, platform), ewald(x, z, EDGE, form, LENGTHS[form]))


@pytest.mark.parametrize("platform", PLATFORMS)
def test_an_excluded_pair_has_no_interaction(platform):
    x, z = configuration(24, seed=5)
    form, length = "slater", LENGTHS["slater"]
    pair = (0, 2)  # valences +1 and +2
    d = x[pair[0]] - x[pair[1]]
    d -= EDGE * np.round(d / EDGE)
    x[pair[1]] = x[pair[0]] - d * 0.8 / np.linalg.norm(d)  # 0.8 r_c apart
    full = evaluate(smeared_system(x, z, form)[0], x, platform)
    excluded = evaluate(smeared_system(x, z, form, excluded=[pair, pair[::-1]])[0], x, platform)
    assert_close(excluded, ewald(x, z, EDGE, form, length, excluded=[pair]))
    # what the exclusion takes away is that pair's smeared energy and force, and no more
    u = BJERRUM * z[pair[0]] * z[pair[1]] * smeared_pair_energy(0.8, form, length)
    assert full[0] - excluded[0] == pytest.approx(u, rel=1e-4)
    h = 1e-6
    slope = (smeared_pair_energy(0.8 + h, form, length) - smeared_pair_energy(0.8 - h, form, length)) / (2 * h)
    pair_force = -BJERRUM * z[pair[0]] * z[pair[1]] * slope * d / np.linalg.norm(d)
    difference = full[1] - excluded[1]
    assert np.allclose(difference[pair[0]], pair_force, rtol=1e-3, atol=1e-3 * np.abs(pair_force).max())
    assert np.allclose(difference[pair[1]], -pair_force, rtol=1e-3, atol=1e-3 * np.abs(pair_force).max())
    others = np.delete(difference, pair, axis=0)
    assert np.abs(others).max() <= 1e-4 * np.abs(full[1]).max()


def isolated_pair(form, platform, valences=(1.0, -1.0)):
    """Energy(r) (kT) of two charges without periodic images: the System's two forces without
    cutoffs, so PME's point charges become Coulomb's law and the correction is summed at any r
    (a platform may need every nonbonded force to agree on the cutoff)."""
    system = periodic_system(2)
    added = add_smeared_electrostatics(system, list(valences), BJERRUM, LENGTHS[form], form)
    isolated = openmm.System()
    isolated.addParticle(1.0)
    isolated.addParticle(1.0)
    point = openmm.XmlSerializer.clone(added.nonbonded)
    point.setNonbondedMethod(openmm.NonbondedForce.NoCutoff)
    correction = openmm.XmlSerializer.clone(added.correction)
    correction.setNonbondedMethod(openmm.CustomNonbondedForce.NoCutoff)
    isolated.addForce(point)
    isolated.addForce(correction)
    properties = {"Threads": "1"} if platform == "CPU" else {}
    context = openmm.Context(isolated, openmm.VerletIntegrator(0.001), openmm.Platform.getPlatformByName(platform),
                             properties)

    def energy(r):
        context.setPositions([openmm.Vec3(0, 0, 0), openmm.Vec3(r, 0, 0)])
        return context.getState(getEnergy=True).getPotentialEnergy().value_in_unit(KJ)
    return energy, added


@pytest.mark.parametrize("platform", PLATFORMS)
@pytest.mark.parametrize("form", FORMS)
def test_two_charges_go_from_a_finite_limit_to_coulomb(form, platform):
    energy, added = isolated_pair(form, platform)
    length = LENGTHS[form]
    limit = -BJERRUM * {"slater": 1.0, "slater-overlap": 5 / 8, "gaussian": 1 / math.sqrt(math.pi)}[form] / length
    assert energy(1e-3) == pytest.approx(limit, rel=1e-4)
    assert energy(1e-3) == pytest.approx(-smeared_pair_limit(form, length, BJERRUM), rel=1e-4)
    for r in (0.1, 0.5, 1.0):
        assert energy(r) == pytest.approx(-smeared_pair_energy(r, form, length, BJERRUM), rel=1e-5)
    # the clouds no longer overlap: Coulomb's law, up to what the correction's cutoff leaves out
    for r in (added.correction_cutoff, 4.0, 7.0):
        assert abs(energy(r) + BJERRUM / r) <= 1e-5
    assert abs(energy(7.0) + BJERRUM / 7.0) <= 1e-6 * BJERRUM / 7.0


def test_the_bjerrum_length_holds_in_any_units():
    x, z = configuration(12, seed=2)
    form = "gaussian"
    reduced = evaluate(smeared_system(x, z, form)[0], x, "Reference")
    model = openmmdpd.DPDUnits(kT=2.5, cutoff=0.7, mass=3.0)
    system = periodic_system(len(z), r_c=0.7)
    add_smeared_electrostatics(system, z, BJERRUM, LENGTHS[form], form, units=model, tolerance=1e-6,
                               ewald_tolerance=1e-6)
    assert_close(evaluate(system, x, "Reference", r_c=0.7, kT=2.5), reduced, rel=1e-6)
    # a length Quantity is read in nm: 0.25 r_c of this model is 0.175 nm
    other = periodic_system(len(z), r_c=0.7)
    add_smeared_electrostatics(other, z, BJERRUM * 0.7 * NM, LENGTHS[form] * 0.7 * NM, form, units=model,
                               tolerance=1e-6, ewald_tolerance=1e-6)
    assert_close(evaluate(other, x, "Reference", r_c=0.7, kT=2.5), reduced, rel=1e-6)


def test_the_correction_cutoff_leaves_out_less_than_the_tolerance():
    def left_out(r, form):
        """The correction of two charges 2 and -2 at r: |energy| (kT) and |force| (kT/r_c)."""
        correction = lambda x: BJERRUM * 4 * (smeared_pair_energy(x, form, 0.5) - 1 / x)
        return max(abs(correction(r)), abs(correction(r * 1.0001) - correction(r * 0.9999)) / (0.0002 * r))

    for form in FORMS:
        system = periodic_system(2, edge=20.0)
        added = add_smeared_electrostatics(system, [2, -2], BJERRUM, 0.5, form, tolerance=1e-5)
        assert 0 < added.tail <= 1e-5
        assert added.correction.getCutoffDistance().value_in_unit(NM) == pytest.approx(added.correction_cutoff)
        assert left_out(added.correction_cutoff, form) <= 1.0001e-5
        assert left_out(0.99 * added.correction_cutoff, form) > 1e-5  # and no shorter cutoff would do


def test_force_groups_and_the_returned_forces():
    x, z = configuration(12, seed=4)
    system, added = smeared_system(x, z, "slater")
    assert system.getNumForces() == 2 and added.forces == (added.nonbonded, added.correction)
    added.set_force_group(3, reciprocal_group=4)
    assert {force.getForceGroup() for force in added.forces} == {3}
    assert added.nonbonded.getReciprocalSpaceForceGroup() == 4
    context = openmm.Context(system, openmm.VerletIntegrator(0.001), openmm.Platform.getPlatformByName("Reference"))
    context.setPositions(x)
    energy = lambda groups: context.getState(getEnergy=True, groups=groups).getPotentialEnergy().value_in_unit(KJ)
    assert energy({0, 1, 2}) == 0.0
    assert energy({3}) + energy({4}) == pytest.approx(energy({3, 4}), rel=1e-12)
    assert added.charge_scale == pytest.approx(math.sqrt(BJERRUM / electrostatics.ONE_4PI_EPS0))


# --- Errors -----------------------------------------------------------------------------------

GOOD = dict(charges=[1.0, -1.0], bjerrum_length=1.1, smearing_length=0.3, form="slater")


@pytest.mark.parametrize("change, error, words", [
    (dict(smearing_length=0.0), ValueError, "smearing_length must be > 0"),
    (dict(smearing_length=-0.2), ValueError, "smearing_length must be > 0"),
    (dict(smearing_length="0.3"), TypeError, "smearing_length must be a number"),
    (dict(smearing_length=0.3 * unit.picosecond), TypeError, "smearing_length must be a length"),
    (dict(form="lorentzian"), ValueError, "form must be one of 'slater', 'slater-overlap', 'gaussian'"),
    (dict(bjerrum_length=0.0), ValueError, "bjerrum_length must be > 0"),
    (dict(bjerrum_length=float("inf")), ValueError, "bjerrum_length must be > 0 and finite"),
    (dict(charges=[1.0]), ValueError, "charges must have one valence per particle (2), got 1"),
    (dict(charges=[1.0, None]), TypeError, "charges[1] must be a number"),
    (dict(charges=[1.0, float("nan")]), ValueError, "charges[1] must be finite"),
    (dict(charges=3), TypeError, "charges must be a sequence"),
    (dict(cutoff=2.6), ValueError, "cutoff must be > 0 and at most half the box's smallest width (2.5 r_c)"),
    (dict(cutoff=0.0), ValueError, "cutoff must be > 0"),
    (dict(smearing_length=1.5), ValueError, "more than half the box's smallest width (2.5 r_c)"),
    (dict(tolerance=0.0), ValueError, "tolerance must be in (0, 1)"),
    (dict(ewald_tolerance=2.0), ValueError, "ewald_tolerance must be in (0, 1)"),
    (dict(exclusions=[(0, 0)]), ValueError, "exclusions must pair two different particles in [0, 2)"),
    (dict(exclusions=[(0, 5)]), ValueError, "exclusions must pair two different particles"),
    (dict(exclusions=[0]), TypeError, "exclusions must be pairs of particle indices"),
    (dict(units=1.0), TypeError, "units must be a DPDUnits"),
])
def test_bad_input_names_the_parameter_and_changes_nothing(change, error, words):
    system = periodic_system(2, edge=5.0)
    with pytest.raises(error) as raised:
        add_smeared_electrostatics(system, **{**GOOD, **change})
    assert str(raised.value).startswith("add_smeared_electrostatics: ") and words in str(raised.value)
    assert system.getNumForces() == 0


def test_a_non_periodic_system_is_refused():
    system = periodic_system(2)
    bonds = openmm.HarmonicBondForce()
    system.addForce(bonds)
    with pytest.raises(ValueError, match="system must be periodic"):
        add_smeared_electrostatics(system, **GOOD)
    assert system.getNumForces() == 1
    bonds.setUsesPeriodicBoundaryConditions(True)
    add_smeared_electrostatics(system, **GOOD)
    assert system.getNumForces() == 3


def test_the_pair_functions_name_their_bad_arguments():
    with pytest.raises(ValueError, match="smeared_pair_energy: smearing_length must be > 0"):
        smeared_pair_energy(1.0, "slater", 0.0)
    with pytest.raises(ValueError, match="smeared_pair_energy: r must be finite and >= 0"):
        smeared_pair_energy([-1.0], "slater", 0.3)
    with pytest.raises(ValueError, match="smeared_pair_limit: form must be one of"):
        smeared_pair_limit("cloud", 0.3)
