"""openmmdpd.lammps: the data file and input script written for LAMMPS say every parameter of
the System and integrator, read back and compared with values computed here from the OpenMM
objects themselves: a_ij, gamma_ij = 2 mu_ij friction and r_c for every pair of particles
(through their LAMMPS types), each atom's mass and type, each bond (i, j, K = k/2, r0) and
angle, the box and positions, the temperature, seed, time step, the integrator's fixes, the
special_bonds factors and the shear fix.  What cannot be expressed is refused, naming the
Force or integrator, with nothing written.  (Running the scripts in LAMMPS is not part of
this file.)"""
import math
import os

import numpy as np
import openmm
import pytest
from openmm import unit

import openmmdpd
from openmmdpd import lammps, scenes

N, DENSITY, DT, SEED = 60, 3.0, 0.04, 4242


def value(quantity, target):
    """A Quantity's number(s) in `target`; plain numbers and arrays are taken as in it already."""
    if unit.is_quantity(quantity):
        return quantity.value_in_unit(target)
    return float(quantity) if np.ndim(quantity) == 0 else np.asarray(quantity, dtype=float)


def soft_parameters(system, i, j):
    """(a, cutoff) of particles i and j from the System's DPDSoftRepulsionForce, or None."""
    for force in system.getForces():
        if isinstance(force, openmmdpd.DPDSoftRepulsionForce):
            ti, tj = force.getParticleType(i), force.getParticleType(j)
            for k in range(force.getNumTypePairs()):
                t1, t2, a, rc = force.getTypePairParameters(k)
                if {t1, t2} == {ti, tj}:
                    return value(a, unit.kilojoule_per_mole / unit.nanometer), value(rc, unit.nanometer)
            return (value(force.getDefaultA(), unit.kilojoule_per_mole / unit.nanometer),
                    value(force.getDefaultCutoff(), unit.nanometer))
    return None


def thermostat_parameters(integrator, system, i, j):
    """(gamma_ij = 2 mu_ij friction, cutoff, weight exponent, the transverse friction's gamma and exponent) of particles i and j."""
    ti, tj = integrator.getParticleType(i), integrator.getParticleType(j)
    friction, rc, s = integrator.getDefaultFriction(), integrator.getDefaultCutoff(), integrator.getDefaultWeightExponent()
    perp, s_perp = integrator.getDefaultTransverseFriction(), integrator.getDefaultTransverseWeightExponent()
    for k in range(integrator.getNumTypePairs()):
        t1, t2, f, c = integrator.getTypePairParameters(k)
        if {t1, t2} == {ti, tj}:
            friction, rc, s = f, c, integrator.getTypePairWeightExponent(k)
            perp, s_perp = integrator.getTypePairTransverseFriction(k)
    mi, mj = (value(system.getParticleMass(p), unit.dalton) for p in (i, j))
    two_mu = 2 * mi * mj / (mi + mj)
    rate = unit.picosecond**-1
    return two_mu * value(friction, rate), value(rc, unit.nanometer), s, two_mu * value(perp, rate), s_perp


def expected_pair(system, integrator, i, j):
    """(a, gamma, cutoff, s, gamma_perp, s_perp) LAMMPS must use for particles i and j."""
    soft = soft_parameters(system, i, j)
    return ((0.0 if soft is None else soft[0]),) + thermostat_parameters(integrator, system, i, j)


def check_pairs(system, integrator, data, script, kT):
    style = script.pair_style[0]
    for i in range(system.getNumParticles()):
        for j in range(i + 1, system.getNumParticles()):
            a, gamma, rc, s, gamma_perp, s_perp = expected_pair(system, integrator, i, j)
            ti, tj = sorted((data.types[i], data.types[j]))
            coefficients = script.pair_coeffs[(ti, tj)]
            if style == "dpd":
                assert coefficients == pytest.approx([a, gamma, rc], rel=1e-14) and s == 2 and gamma_perp == 0
            elif style == "dpd/ext":  # a gamma gammaT ws wsT rc, ws = s/2
                assert coefficients == pytest.approx([a, gamma, gamma_perp, s / 2, s_perp / 2, rc], rel=1e-14)
            else:
                assert style == "dpd/fdt" and s == 2 and gamma_perp == 0
                assert coefficients == pytest.approx([a, math.sqrt(2 * kT * gamma), rc], rel=1e-14)


def check_terms(system, data, script):
    """Each bond (i, j, K = k/2, r0) and angle (i, j, k, K = k/2, theta0 in degrees)."""
    bonds, angles = {}, {}
    for force in system.getForces():
        if type(force) is openmm.HarmonicBondForce:
            for k in range(force.getNumBonds()):
                i, j, r0, stiffness = force.getBondParameters(k)
                bonds[(i, j)] = (value(stiffness, unit.kilojoule_per_mole / unit.nanometer**2) / 2,
                                 value(r0, unit.nanometer))
        if type(force) is openmm.HarmonicAngleForce:
            for k in range(force.getNumAngles()):
                i, j, l, theta, stiffness = force.getAngleParameters(k)
                angles[(i, j, l)] = (value(stiffness, unit.kilojoule_per_mole / unit.radian**2) / 2,
                                     math.degrees(value(theta, unit.radian)))
    hybrid = dict(script.commands)["bond_style"][0] == "hybrid" if data.bonds.size else False
    written = {(i, j): tuple(script.bond_coeffs[t][1:] if hybrid else script.bond_coeffs[t]) for t, i, j in data.bonds
               if script.bond_coeffs[t][0] != "table"}
    assert written.keys() == bonds.keys()
    assert all(written[b] == pytest.approx(bonds[b], rel=1e-14) for b in bonds)
    hybrid = dict(script.commands)["angle_style"][0] == "hybrid" if data.angles.size else False
    written = {(i, j, l): tuple(script.angle_coeffs[t][1:] if hybrid else script.angle_coeffs[t])
               for t, i, j, l in data.angles if script.angle_coeffs[t][0] != "table"}
    assert written.keys() == angles.keys()
    assert all(written[b] == pytest.approx(angles[b], rel=1e-14) for b in angles)


def check_ghost_cutoff(system, kT, written, pair_cutoff, skin=0.3, longest=0.0):
    """Ghost atoms reach every bonded partner: a harmonic bond of constant k has components of
    standard deviation sqrt(kT/k), so 8 of them beyond r0 (twice that across an angle) plus the
    neighbour skin, where that exceeds LAMMPS's default of the pair cutoff plus the skin;
    `longest` is the longest other bond."""
    angles = False
    for force in system.getForces():
        if isinstance(force, openmm.HarmonicBondForce):
            for b in range(force.getNumBonds()):
                _, _, r0, k = force.getBondParameters(b)
                k = value(k, unit.kilojoule_per_mole / unit.nanometer**2)
                if k > 0:
                    longest = max(longest, value(r0, unit.nanometer) + 8 * math.sqrt(kT / k))
        angles |= isinstance(force, openmm.HarmonicAngleForce) and force.getNumAngles() > 0
    reach = (2 * longest if angles else longest) + skin
    if reach <= pair_cutoff + skin:
        assert written == []
    else:
        assert written[0] == "cutoff" and reach <= float(written[1]) < reach + 0.01


def fixes_of(script):
    return {fix: arguments[1] for fix, arguments in script.fixes.items()}


def export(system, integrator, source, tmp_path, **options):
    files = lammps.export_lammps(system, integrator, source, os.fspath(tmp_path / "model"), **options)
    table = os.fspath(tmp_path / "model.table") if os.path.exists(tmp_path / "model.table") else None
    assert files == (os.fspath(tmp_path / "model.data"), os.fspath(tmp_path / "model.in"), table)
    return lammps.read_lammps_data(files.data), lammps.read_lammps_input(files.input)


def check_export(system, integrator, positions, tmp_path, box, velocities=None, longest_bond=0.0, **options):
    """Export, read back and check everything but the special_bonds and the integrator's fixes (and
    the tables of tabulated bonds, whose longest length is `longest_bond`)."""
    data, script = export(system, integrator, positions, tmp_path, velocities=velocities, **options)
    kT = openmmdpd.kT_from_temperature(integrator.getTemperature())
    n = system.getNumParticles()
    assert [data.masses[t] for t in data.types] == [value(system.getParticleMass(i), unit.dalton) for i in range(n)]
    assert len(data.masses) == len(set(data.types)) == max(data.types)
    check_pairs(system, integrator, data, script, kT)
    check_terms(system, data, script)
    assert data.box == pytest.approx(np.asarray(box), abs=1e-14)
    unwrapped = data.positions + data.images @ data.box
    assert unwrapped == pytest.approx(np.asarray(value(positions, unit.nanometer)), abs=1e-12)
    fractions = np.linalg.solve(data.box.T, data.positions.T).T
    assert np.all((fractions >= 0) & (fractions < 1))
    if velocities is not None:  # in the frame of LAMMPS's flow, rate (y - ylo), not rate (y - Ly/2)
        expected = np.array(value(velocities, unit.nanometer / unit.picosecond))
        expected[:, 0] += value(integrator.getShearRate(), unit.picosecond**-1) * np.asarray(box)[1, 1] / 2
        assert data.velocities == pytest.approx(expected)
    assert [float(x) for x in script.pair_style[1:3]] == pytest.approx(
        [kT, max(row[-1] for row in script.pair_coeffs.values())], rel=1e-14)
    assert int(script.pair_style[3]) == options.get("seed", integrator.getRandomNumberSeed())
    commands = dict(script.commands)
    assert commands["units"] == ["lj"] and commands["comm_modify"][:2] == ["vel", "yes"]
    check_ghost_cutoff(system, kT, commands["comm_modify"][2:], max(row[-1] for row in script.pair_coeffs.values()),
                       longest=longest_bond)
    assert float(commands["timestep"][0]) == value(integrator.getStepSize(), unit.picosecond)
    return data, script


def two_type_fluid():
    """A two-type soft fluid whose thermostat types differ from its soft types, with two masses."""
    types = [i % 2 for i in range(N)]
    scene = scenes.soft_scene(num_particles=N, density=DENSITY, a=[[25.0, 40.0], [40.0, 25.0]],
                              soft_repulsion_types=types)
    for i in range(0, N, 5):
        scene.system.setParticleMass(i, 2.0)
    integrator = openmmdpd.DPDVVIntegrator(openmmdpd.KT_TEMPERATURE, 4.5, 1.0, DT)
    integrator.setRandomNumberSeed(SEED)
    for i in range(0, N, 3):
        integrator.setParticleType(i, 1)
    integrator.addTypePair(0, 1, 3.0, 1.0)
    integrator.addTypePair(1, 1, 6.0, 1.0)
    return scene, integrator


def box_of(system):
    return [list(value(v, unit.nanometer)) for v in system.getDefaultPeriodicBoxVectors()]


def test_a_two_type_fluid_with_other_thermostat_types_and_masses(tmp_path):
    scene, integrator = two_type_fluid()
    rng = np.random.default_rng(3)
    velocities = rng.normal(size=(N, 3))
    # Positions outside the box: written wrapped, with image flags that restore them.
    positions = scene.positions.value_in_unit(unit.nanometer) + rng.integers(-2, 3, size=(N, 3)) * box_of(scene.system)[0][0]
    data, script = check_export(scene.system, integrator, positions, tmp_path, box_of(scene.system),
                                velocities=velocities, steps=500)
    # (soft type, thermostat type, mass): 2 x 2 x 2 combinations, all present.
    assert len(data.masses) == 8 and script.pair_style[0] == "dpd"
    assert fixes_of(script) == {"integrate": "nve"}
    assert script.special_bonds == ["lj", "1.0", "1.0", "1.0"]
    assert dict(script.commands)["run"] == ["500"]
    assert "velocity" not in dict(script.commands)
    assert any("T* = kT / (1 kJ/mol)" in line for line in script.header)


def chains_system():
    """Chains of 5 beads in the fluid: harmonic bonds (two kinds), angles, bonded pairs
    excluded from the repulsion and from the thermostat (special_bonds lj 0 1 1)."""
    scene, integrator = two_type_fluid()
    system = scene.system
    chains = [list(range(c, c + 5)) for c in range(0, 20, 5)]
    bonds = [(i, j) for chain in chains for i, j in zip(chain[:-1], chain[1:])]
    springs = openmm.HarmonicBondForce()
    angles = openmm.HarmonicAngleForce()
    for k, (i, j) in enumerate(bonds):
        springs.addBond(i, j, 0.5 if k % 2 else 0.0, 100.0 if k % 2 else 4.0)
    for chain in chains:
        for i, j, l in zip(chain, chain[1:], chain[2:]):
            angles.addAngle(i, j, l, math.pi if j % 2 else 2.0, 6.0)
    springs.setUsesPeriodicBoundaryConditions(True)
    angles.setUsesPeriodicBoundaryConditions(True)
    system.addForce(springs)
    system.addForce(angles)
    soft = next(f for f in system.getForces() if isinstance(f, openmmdpd.DPDSoftRepulsionForce))
    for i, j in bonds:
        soft.addExclusion(i, j)
    integrator.createThermostatExceptionsFromBonds(bonds, 0.0, 1.0)
    system.addForce(openmm.CMMotionRemover(10))
    return scene, integrator, chains


def test_chains_with_bonds_angles_and_special_bonds(tmp_path):
    scene, integrator, chains = chains_system()
    data, script = check_export(scene.system, integrator, scene.positions, tmp_path, box_of(scene.system),
                                topology=scene.topology)
    assert len(script.bond_coeffs) == 2 and len(script.angle_coeffs) == 2
    with open(tmp_path / "model.data") as f:
        masses = f.read().split("Masses")[1].split("Atoms")[0]
    assert masses.count(", atoms S\n") == len(data.masses)  # the topology's atom names beside each type
    assert dict(script.commands)["atom_style"] == ["molecular"]
    assert script.special_bonds == ["lj", "0.0", "1.0", "1.0"]
    assert script.fixes["momentum"] == ["all", "momentum", "10", "linear", "1", "1", "1"]
    assert [len(set(data.molecules[chain])) for chain in chains] == [1] * len(chains)
    assert len({data.molecules[chain[0]] for chain in chains}) == len(chains) and not any(data.molecules[20:])
    # No velocities given: the script draws them at kT with the seed.
    assert dict(script.commands)["velocity"] == ["all", "create", "1.0", str(SEED), "dist", "gaussian", "mom", "yes"]


FENE_K, FENE_RMAX, WLC_LP, WLC_L = 7.0, 3.0, 0.5, 2.0


def fene(r):
    """(energy, -dE/dr) of scenes.fene_bond_force's springs, written out here."""
    x = (r / FENE_RMAX) ** 2
    return -FENE_K / 2 * FENE_RMAX**2 * np.log(1 - x), -FENE_K * r / (1 - x)


def wlc(r, kT=1.0):
    """(energy, -dE/dr) of Marko and Siggia's springs as scenes.wlc_bond_force writes them."""
    R = r / WLC_L
    return (kT / WLC_LP * WLC_L * (0.25 / (1 - R) - 0.25 - 0.25 * R + 0.5 * R**2),
            -kT / WLC_LP * (0.25 / (1 - R)**2 - 0.25 + R))


def spring(kb, r0):
    return lambda r: (kb / 2 * (r - r0) ** 2, -kb * (r - r0))


def tabulated_bonds_system():
    """The rho 3 fluid (box 5.1) with chains joined by FENE, worm-like and harmonic springs, and
    a CustomBondForce with per-bond parameters: {bond (i, j): its (energy, force) function}."""
    scene = scenes.soft_scene(num_particles=400, density=DENSITY, a=25.0)
    system = scene.system
    expected = {}
    fene_bonds, wlc_bonds = [(0, 1), (1, 2)], [(3, 4), (4, 5)]
    system.addForce(scenes.fene_bond_force(fene_bonds, k=FENE_K, rmax=FENE_RMAX))
    system.addForce(scenes.wlc_bond_force(wlc_bonds, WLC_LP, WLC_L))
    expected.update({b: fene for b in fene_bonds})
    expected.update({b: wlc for b in wlc_bonds})
    custom = openmm.CustomBondForce("0.5*kb*(r-r0)^2")
    custom.addPerBondParameter("kb")
    custom.addPerBondParameter("r0")
    for (i, j), (kb, r0) in zip([(6, 7), (7, 8), (9, 10)], [(50.0, 0.5), (50.0, 0.5), (20.0, 0.0)]):
        custom.addBond(i, j, [kb, r0])
        expected[(i, j)] = spring(kb, r0)
    custom.setUsesPeriodicBoundaryConditions(True)
    system.addForce(custom)
    springs = openmm.HarmonicBondForce()
    springs.addBond(11, 12, 0.0, 4.0)
    springs.setUsesPeriodicBoundaryConditions(True)
    system.addForce(springs)
    integrator = openmmdpd.DPDVVIntegrator(openmmdpd.KT_TEMPERATURE, 4.5, 1.0, DT)
    integrator.setRandomNumberSeed(SEED)
    return scene, integrator, expected


def test_custom_bonds_are_tabulated_as_openmm_computes_them(tmp_path):
    """FENE, worm-like and per-bond-parameter springs become bond_style table sections (hybrid with
    the harmonic bond), one per distinct bond, whose energies and forces are the springs' own,
    from r = 0 to where the energy first passes its minimum by 32 kT."""
    from openmmdpd import lammps_tables
    scene, integrator, expected = tabulated_bonds_system()
    kT = openmmdpd.kT_from_temperature(integrator.getTemperature())
    ends = {}
    for function in set(expected.values()):
        r = np.arange(0, 2.55, 1e-4)
        with np.errstate(invalid="ignore", divide="ignore"):
            energy = function(r)[0]
        past = ~np.isfinite(energy) | (energy - np.fmin.accumulate(energy) > 32 * kT)  # above the lowest so far
        ends[function] = r[np.argmax(past)]
    data, script = check_export(scene.system, integrator, scene.positions, tmp_path, box_of(scene.system),
                                longest_bond=max(ends.values()))
    assert dict(script.commands)["bond_style"] == ["hybrid", "harmonic", "table", "linear", "2000"]
    tables = lammps_tables.read_tables(tmp_path / "model.table")
    types = {(i, j): t for t, i, j in data.bonds}
    assert len(tables) == 4  # FENE, the worm-like chain and two distinct springs
    for bond, function in expected.items():
        style, name, keyword = script.bond_coeffs[types[bond]]
        assert (style, name) == ("table", "model.table")
        table = tables[keyword]
        assert table.points[0] == 0 and len(table.points) == 2000
        assert ends[function] - 2e-3 < table.points[-1] <= ends[function]
        energy, force = function(table.points[1:])
        assert table.energies[1:] == pytest.approx(energy, rel=1e-9, abs=1e-9)
        assert table.forces[1:] == pytest.approx(force, rel=1e-6, abs=1e-9)
        assert table.forces[0] == pytest.approx(function(np.array([0.0]))[1][0], abs=1e-4)


def test_custom_angles_are_tabulated_from_0_to_180_degrees(tmp_path):
    """Cosine angles k (1 - cos(theta - theta0)) with per-angle parameters, beside a harmonic angle:
    angle_style hybrid, and each table's energies and -dE/dtheta per degree those of the formula."""
    from openmmdpd import lammps_tables
    scene, integrator, chains = chains_system()
    cosine = openmm.CustomAngleForce("k*(1 - cos(theta - theta0))")
    cosine.addPerAngleParameter("k")
    cosine.addPerAngleParameter("theta0")
    parameters = {(0, 1, 2): (6.0, math.pi), (5, 6, 7): (6.0, math.pi), (10, 11, 12): (3.0, 2.0)}
    for atoms, values in parameters.items():
        cosine.addAngle(*atoms, list(values))
    cosine.setUsesPeriodicBoundaryConditions(True)
    scene.system.addForce(cosine)
    data, script = check_export(scene.system, integrator, scene.positions, tmp_path, box_of(scene.system))
    assert dict(script.commands)["angle_style"] == ["hybrid", "harmonic", "table", "linear", "1801"]
    tables = lammps_tables.read_tables(tmp_path / "model.table")
    tabulated = {(i, j, l): script.angle_coeffs[t] for t, i, j, l in data.angles if script.angle_coeffs[t][0] == "table"}
    assert tabulated.keys() == parameters.keys() and len({c[2] for c in tabulated.values()}) == 2
    for atoms, (k, theta0) in parameters.items():
        table = tables[tabulated[atoms][2]]
        assert table.points == pytest.approx(np.linspace(0, 180, 1801), abs=1e-12)
        theta = np.radians(table.points[1:-1])
        assert table.energies[1:-1] == pytest.approx(k * (1 - np.cos(theta - theta0)), rel=1e-9, abs=1e-9)
        assert table.forces[1:-1] == pytest.approx(-k * np.sin(theta - theta0) * np.pi / 180, rel=1e-6, abs=1e-9)


def test_a_bond_that_never_stiffens_within_half_the_box_is_refused(tmp_path):
    scene, integrator = two_type_fluid()
    flat = openmm.CustomBondForce("0.01*r")
    flat.addBond(0, 1, [])
    scene.system.addForce(flat)
    with pytest.raises(ValueError, match="stays within 32 kT of its minimum out to"):
        lammps.export_lammps(scene.system, integrator, scene.positions, os.fspath(tmp_path / "model"))
    assert os.listdir(tmp_path) == []


def test_weight_exponents_write_dpd_ext(tmp_path):
    scene, integrator = two_type_fluid()
    integrator.setDefaultWeightExponent(1.0)
    integrator.setTypePairWeightExponent(1, 0.5)
    data, script = check_export(scene.system, integrator, scene.positions, tmp_path, box_of(scene.system),
                                seed=17)
    assert script.pair_style[0] == "dpd/ext" and script.pair_style[3] == "17"
    assert {row[3] for row in script.pair_coeffs.values()} == {0.5, 0.25}


def test_transverse_friction_writes_dpd_ext(tmp_path):
    scene, integrator = two_type_fluid()
    integrator.setDefaultTransverseFriction(2.0)
    integrator.setTypePairTransverseFriction(1, 5.0, 1.0)
    data, script = check_export(scene.system, integrator, scene.positions, tmp_path, box_of(scene.system))
    assert script.pair_style[0] == "dpd/ext"
    assert {row[4] for row in script.pair_coeffs.values()} == {1.0, 0.5}  # ws_perp = s_perp / 2
    assert all(row[2] > 0 for row in script.pair_coeffs.values())


def test_shardlow_with_transverse_friction_is_refused(tmp_path):
    scene, _ = two_type_fluid()
    integrator = openmmdpd.ShardlowIntegrator(openmmdpd.KT_TEMPERATURE, 4.5, 1.0, DT)
    integrator.setRandomNumberSeed(SEED)
    integrator.setDefaultTransverseFriction(4.5)
    with pytest.raises(ValueError, match="pair dpd/fdt has no transverse friction"):
        lammps.export_lammps(scene.system, integrator, scene.positions, os.fspath(tmp_path / "model"))
    assert os.listdir(tmp_path) == []


def test_shardlow_order_1_writes_fix_shardlow_and_dpd_fdt(tmp_path):
    scene, _ = two_type_fluid()
    integrator = openmmdpd.ShardlowIntegrator(openmmdpd.reduced_temperature(1.5), 4.5, 1.0, DT)
    integrator.setRandomNumberSeed(SEED)
    integrator.addTypePair(0, 1, 2.0, 1.0)
    integrator.setParticleType(3, 1)
    soft = next(f for f in scene.system.getForces() if isinstance(f, openmmdpd.DPDSoftRepulsionForce))
    soft.setTypePairParameters(1, 1, 1, 0.0, 1.0)  # a = 0 between type-1 beads
    data, script = check_export(scene.system, integrator, scene.positions, tmp_path, box_of(scene.system))
    assert script.pair_style[0] == "dpd/fdt" and float(script.pair_style[1]) == pytest.approx(1.5, rel=1e-14)
    fixes = [arguments[2] for command, arguments in script.commands if command == "fix"]
    assert fixes == ["shardlow", "nve"]  # LAMMPS requires fix shardlow first
    pair_lines = [arguments for command, arguments in script.commands if command == "pair_coeff"]
    assert float(pair_lines[-1][2]) != 0  # dpd/fdt drops all conservative forces if its last a is 0


def test_shear_from_a_context_writes_a_tilted_box_and_fix_deform(tmp_path):
    scene, integrator = two_type_fluid()
    integrator.setShearRate(0.2)
    context = openmm.Context(scene.system, integrator, openmm.Platform.getPlatformByName("Reference"))
    context.setPositions(scene.positions)
    context.setVelocitiesToTemperature(openmmdpd.KT_TEMPERATURE, 1)
    integrator.step(5)
    state = context.getState(getPositions=True, getVelocities=True)
    box = [list(value(v, unit.nanometer)) for v in state.getPeriodicBoxVectors()]
    assert box[1][0] != 0
    data, script = check_export(scene.system, integrator, state.getPositions(), tmp_path, box,
                                velocities=state.getVelocities(), box_vectors=state.getPeriodicBoxVectors())
    from_context, _ = export(scene.system, integrator, context, tmp_path)
    assert from_context.box == pytest.approx(data.box) and from_context.positions == pytest.approx(data.positions)
    assert from_context.velocities == pytest.approx(data.velocities)
    check_round_trip(scene.system, integrator, state.getPositions(), tmp_path, box, velocities=state.getVelocities(),
                     box_vectors=state.getPeriodicBoxVectors())
    # These velocities carry a net momentum along y, which LAMMPS would count as heat under shear: said
    assert any(line.startswith("WARNING: the centre of mass moves at") for line in script.header)
    velocities = state.getVelocities(asNumpy=True).value_in_unit(unit.nanometer / unit.picosecond)
    masses = np.array([value(scene.system.getParticleMass(i), unit.dalton) for i in range(N)])
    _, still = export(scene.system, integrator, state.getPositions(), tmp_path, velocities=velocities - masses @ velocities
                      / masses.sum(), box_vectors=state.getPeriodicBoxVectors())
    assert not any(line.startswith("WARNING") for line in still.header)
    assert script.fixes["shear"] == ["all", "deform", "1", "xy", "erate", "0.2", "remap", "v", "flip", "yes"]
    assert script.fixes["integrate"] == ["all", "nve"]
    # LAMMPS reports the temperature and pressure of the velocities less the flow, as the pressure tensor here
    commands = dict(script.commands)
    assert commands["compute"] == ["peculiar", "all", "temp/deform"]
    assert commands["thermo_modify"] == ["temp", "peculiar"]


def test_a_fluid_without_conservative_force(tmp_path):
    scene = scenes.ideal_scene(num_particles=N, density=DENSITY)
    integrator = openmmdpd.DPDVVIntegrator(openmmdpd.KT_TEMPERATURE, 4.5, 1.0, DT)
    integrator.setRandomNumberSeed(SEED)
    data, script = check_export(scene.system, integrator, scene.positions, tmp_path, box_of(scene.system))
    assert script.pair_coeffs == {(1, 1): [0.0, 4.5, 1.0]}


def test_approximate_writes_the_closest_scheme_and_says_so(tmp_path):
    scene, integrator = two_type_fluid()
    integrator.setLambda(0.65)
    data, script = check_export(scene.system, integrator, scene.positions, tmp_path, box_of(scene.system),
                                approximate=True)
    assert fixes_of(script) == {"integrate": "nve"}
    assert any(line.startswith("WARNING: approximate: DPDVVIntegrator (GrootWarren, lambda 0.65)")
               for line in script.header)


def lowe():
    integrator = openmmdpd.LoweAndersenIntegrator(openmmdpd.KT_TEMPERATURE, 4.5, 1.0, DT)
    integrator.setRandomNumberSeed(SEED)
    return integrator


def dpdvv_variant():
    integrator = openmmdpd.DPDVVIntegrator(openmmdpd.KT_TEMPERATURE, 4.5, 1.0, DT)
    integrator.setVariant(openmmdpd.DPDVVIntegrator.DPDVV)
    integrator.setRandomNumberSeed(SEED)
    return integrator


def with_charges(scene):
    force = openmm.NonbondedForce()
    for i in range(N):
        force.addParticle(0.1 if i % 2 else -0.1, 0.3, 0.0)
    scene.system.addForce(force)


def with_wca():
    return scenes.polymer_scene(num_particles=N, density=DENSITY, chain_length=5)


def unequal_cutoffs(scene, integrator):
    integrator.addTypePair(0, 0, 4.5, 0.9)


def fractional_bond_factor(scene, integrator):
    springs = openmm.HarmonicBondForce()
    springs.addBond(0, 1, 0.0, 4.0)
    scene.system.addForce(springs)
    integrator.addThermostatException(0, 1, 0.5)


def far_exception(scene, integrator):
    soft = next(f for f in scene.system.getForces() if isinstance(f, openmmdpd.DPDSoftRepulsionForce))
    soft.addExclusion(0, 7)
    integrator.addThermostatException(0, 7, 0.0)


def shardlow_under_shear():
    integrator = openmmdpd.ShardlowIntegrator(openmmdpd.KT_TEMPERATURE, 4.5, 1.0, DT)
    integrator.setRandomNumberSeed(SEED)
    integrator.setShearRate(0.1)
    return integrator


REFUSALS = {
    "a CustomNonbondedForce": (lambda s, i: None, with_wca, None, "CustomNonbondedForce 'WCA'"),
    "a NonbondedForce with charges": (lambda s, i: with_charges(s), None, None, "NonbondedForce"),
    "Lowe-Andersen collisions": (lambda s, i: None, None, lowe, "LoweAndersenIntegrator (Lowe)"),
    "DPD-VV": (lambda s, i: None, None, dpdvv_variant, "DPDVVIntegrator (DPDVV) has no LAMMPS equivalent"),
    "seed 0": (lambda s, i: i.setRandomNumberSeed(0), None, None, "seed must be an integer from 1"),
    "cutoffs that differ": (unequal_cutoffs, None, None, "LAMMPS's pair dpd has one cutoff per pair of types"),
    "a factor the soft force lacks": (fractional_bond_factor, None, None, "the soft-repulsion factor 1.0"),
    "an exception not along bonds": (far_exception, None, None, "are not 1, 2 or 3 bonds apart"),
    "Shardlow under shear": (lambda s, i: None, None, shardlow_under_shear, "fix shardlow supports only orthogonal"),
}


@pytest.mark.parametrize("case", sorted(REFUSALS))
def test_what_cannot_be_expressed_is_refused_with_nothing_written(case, tmp_path):
    change, make_scene, make_integrator, message = REFUSALS[case]
    scene, integrator = two_type_fluid()
    scene = make_scene() if make_scene else scene
    integrator = make_integrator() if make_integrator else integrator
    change(scene, integrator)
    with pytest.raises(ValueError, match="export_lammps: ") as error:
        lammps.export_lammps(scene.system, integrator, scene.positions, os.fspath(tmp_path / "model"),
                             approximate=case == "Lowe-Andersen collisions")
    assert message in str(error.value)
    assert os.listdir(tmp_path) == []


def test_a_force_field_model_with_shardlow(tmp_path):
    """The Groot–Madden diblock melt, built from its force field as the examples do, with
    removeCMMotion left on: repulsion, bonds and the force field's thermostat table."""
    from openmm import app
    from openmmdpd import forcefield, packer
    ff = app.ForceField(forcefield.data_path("groot-madden-diblock.xml"))
    chain = packer.Molecule.linear(["A"] * 5 + ["B"] * 5)
    topology, positions = packer.pack([(chain, 12)], box=[3.5] * 3, bond_length=0.8, seed=4)
    system = ff.createSystem(topology, nonbondedMethod=app.CutoffPeriodic)
    integrator = openmmdpd.ShardlowIntegrator(openmmdpd.KT_TEMPERATURE, 4.5, 1.0, DT)
    forcefield.apply_thermostat_parameters(integrator, ff, topology)
    integrator.setRandomNumberSeed(SEED)
    data, script = check_export(system, integrator, positions, tmp_path, box_of(system), topology=topology)
    assert sorted(script.pair_coeffs[(1, 2)][:1] + script.pair_coeffs[(1, 1)][:1]) == [25.0, 40.0]
    assert len(data.bonds) == 12 * 9 and script.bond_coeffs == {1: [2.0, 0.0]}  # K = k/2 = 4/2
    assert script.special_bonds == ["lj", "1.0", "1.0", "1.0"]  # bonded beads repel in this model
    assert script.fixes["momentum"][:3] == ["all", "momentum", "1"]


def test_the_side_by_side_check_reads_a_lammps_dump_by_atom_id(tmp_path):
    from openmmdpd.lammps_check import dump_frames
    header = ("ITEM: TIMESTEP\n{}\nITEM: NUMBER OF ATOMS\n2\nITEM: BOX BOUNDS pp pp pp\n0 2\n0 2\n0 2\n"
              "ITEM: ATOMS id x y z\n")
    dump = tmp_path / "frames.dump"
    dump.write_text(header.format(0) + "2 1.0 1.1 1.2\n1 0.0 0.1 0.2\n"
                    + header.format(250) + "1 0.5 0.6 0.7\n2 1.5 1.6 1.7\n")
    frames = dump_frames(dump)
    assert frames.tolist() == [[[0.0, 0.1, 0.2], [1.0, 1.1, 1.2]], [[0.5, 0.6, 0.7], [1.5, 1.6, 1.7]]]


def test_the_side_by_side_check_records_its_command_without_the_machines_lammps():
    from openmmdpd.lammps_check import _command
    assert _command(["--lmp", "/somewhere/lmp", "--steps", "10"]) == "bash scripts/lammps-check.sh --steps 10"
    assert _command(["--lmp=/x/lmp", "--out", "t.md"]) == "bash scripts/lammps-check.sh --out t.md"


def test_the_side_by_side_check_reads_a_lammps_thermo_log(tmp_path):
    """openmmdpd.lammps_check's reader: the rows under `Step Temp Press`, up to `Loop`."""
    from openmmdpd.lammps_check import thermo_rows
    log = tmp_path / "log.lammps"
    log.write_text("LAMMPS (7 Jan 2022)\nrun 40\nPer MPI rank memory\n   Step          Temp          Press    \n"
                   "         0    1.02           23.9     \n        20    1.03           23.8     \n"
                   "Loop time of 0.5 on 1 procs for 40 steps with 3000 atoms\n   Step Temp Press\n 99 9 9\n")
    rows = thermo_rows(log)
    assert rows.tolist() == [[0.0, 1.02, 23.9], [20.0, 1.03, 23.8]]


# --- Reading an export back (openmmdpd.lammps_import) -------------------------------------------

def forces_and_energy(system, positions, box):
    context = openmm.Context(system, openmm.VerletIntegrator(0.001), openmm.Platform.getPlatformByName("Reference"))
    context.setPeriodicBoxVectors(*box)
    context.setPositions(positions)
    state = context.getState(getForces=True, getEnergy=True)
    return (state.getForces(asNumpy=True).value_in_unit(unit.kilojoule_per_mole / unit.nanometer),
            state.getPotentialEnergy().value_in_unit(unit.kilojoule_per_mole))


def exception_factors(integrator):
    factors = {}
    for k in range(integrator.getNumThermostatExceptions()):
        i, j, factor = integrator.getThermostatExceptionParameters(k)
        if factor != 1:
            factors[(min(i, j), max(i, j))] = factor
    return factors


def check_round_trip(system, integrator, positions, tmp_path, box=None, **options):
    """Export, read back with read_lammps_model, and compare: the forces and energy at the same
    positions, every pair's thermostat parameters and factor, the integrator's settings."""
    from openmmdpd.lammps_import import read_lammps_model
    lammps.export_lammps(system, integrator, positions, os.fspath(tmp_path / "model"), steps=7, **options)
    back = read_lammps_model(tmp_path / "model")
    box = box or box_of(system)
    positions = np.asarray(value(positions, unit.nanometer))
    if "velocities" in options:
        assert back.velocities == pytest.approx(np.asarray(value(options["velocities"], unit.nanometer / unit.picosecond)),
                                                abs=1e-12)
    assert back.positions == pytest.approx(positions, abs=1e-12) and back.steps == 7
    assert np.array([list(v) for v in back.box]) == pytest.approx(np.array(box), abs=1e-14)
    forces, energy = forces_and_energy(system, positions, box)
    forces_back, energy_back = forces_and_energy(back.system, back.positions, back.box)
    assert forces_back == pytest.approx(forces, rel=1e-12, abs=1e-10) and energy_back == pytest.approx(energy, rel=1e-12)
    n = system.getNumParticles()
    assert [value(back.system.getParticleMass(i), unit.dalton) for i in range(n)] == \
        [value(system.getParticleMass(i), unit.dalton) for i in range(n)]
    for i in range(n):
        for j in range(i + 1, n):
            assert thermostat_parameters(back.integrator, back.system, i, j) == \
                pytest.approx(thermostat_parameters(integrator, system, i, j), rel=1e-12)
    assert exception_factors(back.integrator) == exception_factors(integrator)
    assert type(back.integrator) is type(integrator)
    for getter, target in (("getTemperature", unit.kelvin), ("getStepSize", unit.picosecond),
                           ("getShearRate", unit.picosecond**-1)):
        assert value(getattr(back.integrator, getter)(), target) == pytest.approx(value(getattr(integrator, getter)(), target),
                                                                                rel=1e-14)
    assert back.integrator.getRandomNumberSeed() == options.get("seed", integrator.getRandomNumberSeed())
    removers = [[f.getFrequency() for f in s.getForces() if isinstance(f, openmm.CMMotionRemover)]
                for s in (system, back.system)]
    assert removers[0] == removers[1]
    return back


def test_a_chain_model_comes_back_from_lammps_as_it_went(tmp_path):
    scene, integrator, _ = chains_system()
    back = check_round_trip(scene.system, integrator, scene.positions, tmp_path)
    assert back.velocities is None


def test_weight_exponents_and_shardlow_come_back(tmp_path):
    scene, _ = two_type_fluid()
    integrator = openmmdpd.ShardlowIntegrator(openmmdpd.KT_TEMPERATURE, 4.5, 1.0, DT)
    integrator.setRandomNumberSeed(SEED)
    check_round_trip(scene.system, integrator, scene.positions, tmp_path)
    integrator = openmmdpd.DPDVVIntegrator(2 * openmmdpd.KT_TEMPERATURE, 4.5, 1.0, DT)
    integrator.setRandomNumberSeed(SEED)
    integrator.setDefaultWeightExponent(0.5)
    check_round_trip(scene.system, integrator, scene.positions, tmp_path, seed=77)
    integrator.setDefaultTransverseFriction(3.0)
    integrator.setDefaultTransverseWeightExponent(1.5)
    check_round_trip(scene.system, integrator, scene.positions, tmp_path, seed=78)


def test_a_tabulated_bond_is_not_read_back(tmp_path):
    from openmmdpd.lammps_import import read_lammps_model
    scene, integrator, _ = tabulated_bonds_system()
    lammps.export_lammps(scene.system, integrator, scene.positions, os.fspath(tmp_path / "model"))
    with pytest.raises(ValueError, match="read_lammps_model: bond_style hybrid harmonic table"):
        read_lammps_model(tmp_path / "model")
