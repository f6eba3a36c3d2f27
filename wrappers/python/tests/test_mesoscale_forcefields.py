"""The mesoscale force fields the package ships (groot-madden-diblock.xml, lipid-h3t4.xml,
binary-mixture.xml): each loads with app.ForceField, builds on a small packed system the a_ij,
friction and bonded tables its XML states (and the papers' numbers), equals a System built by
hand, gives an integrator its thermostat, and runs stable at dt 0.04 after packer.relax; the
binary mixture at chi = 3 demixes."""
import math
import re
import xml.etree.ElementTree as ElementTree

import numpy as np
import openmm
import pytest
from openmm import app, unit
from scipy.spatial import cKDTree

import openmmdpd
from openmmdpd import forcefield, packer, scenes

from dpdtest import energy_and_forces, have_opencl, named_pair_table as pair_table, number, soft_force

KT = openmmdpd.KT_TEMPERATURE
FILES = ("groot-madden-diblock.xml", "lipid-h3t4.xml", "binary-mixture.xml")

DIBLOCK = packer.Molecule.linear(["A"] * 3 + ["B"] * 2)
LIPID = packer.Molecule.single("LIPID", ["h1", "h2", "h3"] + [f"t{i}" for i in range(1, 9)],
                               [(0, 1), (1, 2), (2, 3), (3, 4), (4, 5), (5, 6), (2, 7), (7, 8), (8, 9), (9, 10)])


def molecules(name):
    """A small mix of each file's molecules: (molecule, count) pairs, about 600 beads at rho = 3."""
    if name == "groot-madden-diblock.xml":
        # A3B2 chains, a lone A and a lone B: every template of the file in one topology.
        return [(DIBLOCK, 118), (packer.Molecule.single("A", ["A"]), 5), (packer.Molecule.single("B", ["B"]), 5)]
    if name == "lipid-h3t4.xml":
        return [(LIPID, 20), (packer.Molecule.single("w", ["w"]), 380)]
    return [(packer.Molecule.single("A", ["A"]), 300), (packer.Molecule.single("B", ["B"]), 300)]


def packed(name, seed=1):
    bond_length = 0.7 if name == "lipid-h3t4.xml" else 0.8
    return packer.pack(molecules(name), density=3.0, bond_length=bond_length, seed=seed)


def xml_table(name, tag, value):
    """{(type1, type2): (value, cutoff)} of a tag's <Pair> entries as the file writes them."""
    root = ElementTree.parse(forcefield.data_path(name)).getroot()
    return {(p.get("type1"), p.get("type2")): (float(p.get(value)), float(p.get("cutoff")))
            for p in root.find(tag).findall("Pair")}


def created(name, seed=1):
    ff = app.ForceField(forcefield.data_path(name))
    topology, positions = packed(name, seed)
    return ff, topology, positions, ff.createSystem(topology, nonbondedMethod=app.CutoffPeriodic, removeCMMotion=False)


def test_the_files_are_shipped_and_load():
    for name in FILES:
        assert app.ForceField(forcefield.data_path(name)) is not None


def type_names(ff, topology):
    """The bead types present, in the force's numbering; each bead's name starts with its type."""
    return forcefield.bead_types(ff, [atom.name[0] for atom in topology.atoms()])


@pytest.mark.parametrize("name", FILES)
def test_the_force_and_the_thermostat_have_the_files_tables(name):
    ff, topology, _, system = created(name)
    types = type_names(ff, topology)
    expected_a = xml_table(name, "DPDSoftRepulsionForce", "a")
    force_table = pair_table(soft_force(system), types)
    assert len(force_table) == len(expected_a)
    for (t1, t2), values in force_table.items():
        assert values == expected_a.get((t1, t2), expected_a.get((t2, t1)))
    integrator = forcefield.apply_thermostat_parameters(openmmdpd.DPDVVIntegrator(KT, 1.0, 2.0, 0.04), ff, topology)
    assert set(pair_table(integrator, types).values()) == {(4.5, 1.0)}
    particle_types = [soft_force(system).getParticleType(i) for i in range(system.getNumParticles())]
    assert [integrator.getParticleType(i) for i in range(system.getNumParticles())] == particle_types
    assert [system.getParticleMass(i) for i in range(3)] == [1.0 * unit.dalton] * 3


def a_table(name):
    ff, topology, _, system = created(name)
    return pair_table(soft_force(system), type_names(ff, topology))


def test_the_papers_numbers():
    tables = {name: a_table(name) for name in FILES}
    # Like beads 75 kT/rho = 25 at rho = 3 (Groot and Warren 1997) in every file.
    for table in tables.values():
        assert {value for (t1, t2), (value, _) in table.items() if t1 == t2} == {25.0}
    # Groot and Madden: a_AB = 25 + 3.27 chi; the file's chi = 4.59 gives chi N = 46 for N = 10.
    chi = (tables["groot-madden-diblock.xml"][("A", "B")][0] - 25.0) / 3.27
    assert chi == pytest.approx(4.59, abs=0.005) and 10 * chi > 10.5
    # Groot and Warren's monomer mixtures: chi = 0.286 (a_AB - 25) at rho = 3; chi = 3 here.
    assert 0.286 * (tables["binary-mixture.xml"][("A", "B")][0] - 25.0) == pytest.approx(3.0, abs=0.002)
    lipid = tables["lipid-h3t4.xml"]
    assert (lipid[("w", "h")][0], lipid[("h", "t")][0], lipid[("w", "t")][0]) == (25.0, 50.0, 75.0)


def test_each_chi_slope_is_credited_to_its_paper():
    # Groot and Warren's fit at rho = 3 is chi = 0.286 Delta a (Delta a = 3.50 chi); the
    # 3.27 chi often quoted is Groot and Madden's. A header crediting 3.27 to Groot and Warren
    # would say a different a_ij for the same chi than flory_huggins.a_from_chi.
    for name in FILES + ("groot-warren.xml",):
        with open(forcefield.data_path(name)) as f:
            header = " ".join(f.read().split("-->")[0].split())
        for match in re.finditer(r"3\.27", header):
            assert "Madden" in header[max(0, match.start() - 160):match.end() + 160], (name, match.start())
    with open(forcefield.data_path("groot-warren.xml")) as f:
        header = " ".join(f.read().split("-->")[0].split())
    assert "a_WP = 25 + chi/0.286 = 25 + 3.50 chi" in header


def test_the_diblock_system_equals_a_hand_built_one():
    _, topology, positions, system = created("groot-madden-diblock.xml")
    types = [0 if atom.name == "A" else 1 for atom in topology.atoms()]
    expected = openmm.System()
    for _ in types:
        expected.addParticle(1.0)
    expected.setDefaultPeriodicBoxVectors(*topology.getPeriodicBoxVectors())
    expected.addForce(scenes.soft_repulsion_force(len(types), [[25.0, 40.0], [40.0, 25.0]], types))
    expected.addForce(scenes.harmonic_bond_force([(a.index, b.index) for a, b in topology.bonds()], k=4.0))
    (e1, f1), (e2, f2) = energy_and_forces(system, positions), energy_and_forces(expected, positions)
    assert e1 == pytest.approx(e2, rel=1e-12) and np.max(np.abs(f1 - f2)) < 1e-12 * np.max(np.abs(f2))
    bonds = next(f for f in system.getForces() if isinstance(f, openmm.HarmonicBondForce))
    assert bonds.getNumBonds() == 118 * 4  # no bond to the lone beads
    parameters = {tuple(number(v) for v in bonds.getBondParameters(i)[2:]) for i in range(bonds.getNumBonds())}
    assert parameters == {(0.0, 4.0)}


def test_the_lipid_system_equals_a_hand_built_one():
    _, topology, positions, system = created("lipid-h3t4.xml")
    kinds = [atom.name[0] for atom in topology.atoms()]
    types = ["wht".index(kind) for kind in kinds]
    repulsion = [[25.0, 25.0, 75.0], [25.0, 25.0, 50.0], [75.0, 50.0, 25.0]]  # w, h, t
    expected = openmm.System()
    for _ in types:
        expected.addParticle(1.0)
    expected.setDefaultPeriodicBoxVectors(*topology.getPeriodicBoxVectors())
    expected.addForce(scenes.soft_repulsion_force(len(types), repulsion, types))
    bonds = [(a.index, b.index) for a, b in topology.bonds()]
    expected.addForce(scenes.harmonic_bond_force(bonds, k=100.0, length=0.7))
    angles = openmm.CustomAngleForce("6*(1 - cos(theta - pi)); pi=3.141592653589793")
    for lipid in range(20):
        first = 11 * lipid  # h1; the tails t1-t4 and t5-t8 hang on h3 = first + 2
        for tail in (first + 3, first + 7):
            chain = [first + 2, tail, tail + 1, tail + 2, tail + 3]  # h3 and the tail's beads
            for i in range(3):  # h3-t-t, t-t-t, t-t-t
                angles.addAngle(*chain[i:i + 3])
    expected.addForce(angles)
    (e1, f1), (e2, f2) = energy_and_forces(system, positions), energy_and_forces(expected, positions)
    assert e1 == pytest.approx(e2, rel=1e-12) and np.max(np.abs(f1 - f2)) < 1e-12 * np.max(np.abs(f2))
    cosine = next(f for f in system.getForces() if f.getName() == "CosineAngle")
    assert cosine.getNumAngles() == 20 * 6
    assert {tuple(cosine.getAngleParameters(i)[3]) for i in range(cosine.getNumAngles())} == {(6.0, math.pi)}


@pytest.mark.parametrize("name", FILES)
def test_a_relaxed_start_runs_stable_at_dt_004(name):
    ff, topology, positions, system = created(name, seed=2)
    integrator = forcefield.apply_thermostat_parameters(openmmdpd.DPDVVIntegrator(KT, 4.5, 1.0, 0.04), ff, topology)
    integrator.setRandomNumberSeed(5)
    simulation = app.Simulation(topology, system, integrator, openmm.Platform.getPlatformByName("CPU"))
    simulation.context.setPositions(positions)
    packer.relax(simulation)
    simulation.context.setVelocitiesToTemperature(KT, 3)
    simulation.step(200)
    dof = 3 * system.getNumParticles() - 3
    samples = []
    for _ in range(20):
        simulation.step(10)
        state = simulation.context.getState(getEnergy=True)
        samples.append(2 * state.getKineticEnergy().value_in_unit(unit.kilojoule_per_mole) / dof)
        assert math.isfinite(state.getPotentialEnergy().value_in_unit(unit.kilojoule_per_mole))
    # GW-type velocity Verlet at dt 0.04 runs ~2-5 % hot; ~600 beads give kT to ~1 %.
    assert 0.95 < np.mean(samples) < 1.12


# One integrator of the device per file: a sweep, the velocity-Verlet family, Lowe.
OPENCL_INTEGRATORS = {"groot-madden-diblock.xml": lambda: openmmdpd.ShardlowIntegrator(KT, 4.5, 1.0, 0.04),
                      "lipid-h3t4.xml": lambda: openmmdpd.DPDVVIntegrator(KT, 4.5, 1.0, 0.04),
                      "binary-mixture.xml": lambda: openmmdpd.LoweAndersenIntegrator(KT, 4.5, 1.0, 0.04)}


def three_steps(name, ff, topology, system, start, platform_name):
    """Positions and velocities after steps 1 and 3 from the same start (positions, velocities)."""
    integrator = forcefield.apply_thermostat_parameters(OPENCL_INTEGRATORS[name](), ff, topology)
    integrator.setRandomNumberSeed(11)
    context = openmm.Context(system, integrator, openmm.Platform.getPlatformByName(platform_name))
    context.setPositions(start[0])
    context.setVelocities(start[1])
    states = []
    for steps in (1, 2):
        integrator.step(steps)
        state = context.getState(getPositions=True, getVelocities=True)
        states.append((state.getPositions(asNumpy=True).value_in_unit(unit.nanometer),
                       state.getVelocities(asNumpy=True).value_in_unit(unit.nanometer / unit.picosecond)))
    return states


@pytest.mark.skipif(not have_opencl(), reason="no OpenCL platform or no openmmdpd OpenCL plugin")
@pytest.mark.parametrize("name", FILES)
def test_a_force_field_system_follows_the_reference_on_opencl(name):
    # The device's float tolerance (tests/TestGpuPlatform.cpp): 2e-5 of the box in position,
    # 2e-5 of the largest speed in velocity, after 1 and 3 steps of a relaxed start.
    ff, topology, positions, system = created(name, seed=3)
    context = openmm.Context(system, openmm.VerletIntegrator(0.001), openmm.Platform.getPlatformByName("Reference"))
    context.setPositions(positions)
    packer.relax(context)
    context.setVelocitiesToTemperature(KT, 4)
    state = context.getState(getPositions=True, getVelocities=True)
    start = (state.getPositions(), state.getVelocities())
    edge = topology.getPeriodicBoxVectors()[0][0].value_in_unit(unit.nanometer)
    expected = three_steps(name, ff, topology, system, start, "Reference")
    actual = three_steps(name, ff, topology, system, start, "OpenCL")
    for (x, v), (y, u) in zip(expected, actual):
        d = y - x
        d -= edge * np.round(d / edge)  # the nearest image: the two may wrap differently
        assert np.max(np.linalg.norm(d, axis=1)) < 2e-5 * edge
        assert np.max(np.abs(u - v)) < 2e-5 * np.max(np.linalg.norm(v, axis=1))


def test_the_binary_mixture_demixes():
    # chi = 3 is above a 50:50 monomer mixture's critical chi = 2: within 1000 steps ~70 % of the
    # pairs closer than rc are like pairs (50 % when mixed; ~78 % in 3000 beads after 4000 steps).
    ff, topology, positions, system = created("binary-mixture.xml")
    integrator = forcefield.apply_thermostat_parameters(openmmdpd.DPDVVIntegrator(KT, 4.5, 1.0, 0.04), ff, topology)
    integrator.setRandomNumberSeed(3)
    context = openmm.Context(system, integrator, openmm.Platform.getPlatformByName("CPU"))
    context.setPositions(positions)
    packer.relax(context)
    context.setVelocitiesToTemperature(KT, 1)
    is_a = np.array([atom.name == "A" for atom in topology.atoms()])
    edge = topology.getPeriodicBoxVectors()[0][0].value_in_unit(unit.nanometer)

    def like_pairs():
        x = context.getState(getPositions=True).getPositions(asNumpy=True).value_in_unit(unit.nanometer) % edge
        pairs = cKDTree(x, boxsize=edge).query_pairs(1.0, output_type="ndarray")
        return np.mean(is_a[pairs[:, 0]] == is_a[pairs[:, 1]])

    assert abs(like_pairs() - 0.5) < 0.05
    integrator.step(1000)
    assert like_pairs() > 0.62
