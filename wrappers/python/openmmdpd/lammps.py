"""Export a DPD model to LAMMPS (docs/guide/lammps.md): a data file and an input script that run
the same System and thermostat in LAMMPS, and readers that parse both back into numbers.

Units: the reduced units of this package (r_c = 1 nm, m = 1 amu, energies in kJ/mol, 1 ps)
are LAMMPS `units lj` with sigma = 1 nm, m = 1 amu and epsilon = 1 kJ/mol, so tau = 1 ps and
every number but the temperature is written unchanged; the temperature is written as
kT / (1 kJ/mol), the lj temperature (Boltzmann's constant is 1 there).

What maps (anything else is refused, naming it, before a file is written):

- `DPDSoftRepulsionForce` (periodic) and the integrator's thermostat table -> `pair_style dpd`
  (`dpd/ext` where a weight exponent s is not 2, ws = s/2, or where there is transverse
  friction, its gamma_perp and ws_perp = s_perp/2), one `pair_coeff I J a gamma rc` per pair of
  LAMMPS atom types, an atom type per distinct (soft-repulsion type, thermostat type, mass);
  gamma_IJ = 2 mu_IJ friction, and gamma_perp likewise;
- `HarmonicBondForce` -> `bond_style harmonic` (K = k/2, r0); `CustomBondForce` (FENE, worm-like
  chains, any energy of r) -> `bond_style table`, its energy and force evaluated by OpenMM on a
  grid of lengths for each distinct set of per-bond parameters (openmmdpd.lammps_tables), both
  styles together through `bond_style hybrid`; `HarmonicAngleForce` -> `angle_style harmonic`
  (K = k/2, theta0 in degrees), `CustomAngleForce` (cosine angles, any energy of theta) ->
  `angle_style table` likewise; `CMMotionRemover` -> `fix momentum`;
- the soft force's exclusions and the thermostat exceptions -> `special_bonds lj f12 f13 f14`,
  where they are one factor per class of pairs 1, 2 or 3 bonds apart (LAMMPS scales the
  conservative and dissipative forces of such a pair by the factor);
- `DPDVVIntegrator` GrootWarren with lambda 1/2 -> `fix nve` with `pair dpd`;
  `ShardlowIntegrator` order 1 -> `fix shardlow` + `fix nve` with `pair_style dpd/fdt`;
- bonded terms that may stretch past the pair cutoff + skin -> `comm_modify cutoff`, ghost
  atoms out to the longest bonded distance expected at kT (_ghost_cutoff);
- the shear rate -> a triclinic box and `fix deform 1 xy erate rate remap v`, and a
  thermo temperature (`compute temp/deform`) of the velocities less the imposed flow; the
  velocities are written in that flow's frame, rate (y - ylo), shifted by rate Ly/2 along x
  from openmm-dpd's rate (y - Ly/2).
"""
import math
import os
from collections import namedtuple

import numpy as np
import openmm
from openmm import unit

from .dpdplugin import (DenOtterClarkeIntegrator, DPDSoftRepulsionForce, DPDThermostatIntegrator,
                        DPDVVIntegrator, EDPDIntegrator, LoweAndersenIntegrator, ShardlowIntegrator,
                        StaggeredDPDIntegrator)
from .lammps_tables import ANGLE_POINTS, BOND_ENERGY_LIMIT, TABLE_POINTS, table_text, tabulate_angle, tabulate_bond
from .units import kT_from_temperature

__all__ = ["export_lammps", "read_lammps_data", "read_lammps_input", "LammpsFiles", "LammpsData",
           "LammpsInput", "MAX_SEED"]

#: The largest seed LAMMPS's Marsaglia generator takes (pair dpd adds the rank of the process).
MAX_SEED = 900000000

#: LAMMPS's neighbour-list skin (lj units), written into the script.
SKIN = 0.3

LammpsFiles = namedtuple("LammpsFiles", "data input table")
LammpsFiles.__doc__ = """The paths export_lammps wrote: the data file, the input script and the table
file of bonds and angles (None where none is tabulated)."""

LammpsData = namedtuple("LammpsData", "masses types molecules positions images velocities bonds angles box")
LammpsData.__doc__ = """A LAMMPS data file read back (read_lammps_data), atoms in the order of their ids.

masses: {atom type: mass}; types, molecules: (N,) ints; positions: (N, 3) in the box; images:
(N, 3) image flags (unwrapped = positions + images @ box); velocities: (N, 3) or None; bonds:
(M, 3) ints (type, atom index, atom index), indices from 0; angles: (K, 4) likewise; box: 3 x 3
rows a, b, c (LAMMPS's xhi - xlo, (xy, yhi - ylo, 0), (xz, yz, zhi - zlo))."""

LammpsInput = namedtuple("LammpsInput", "header commands pair_style pair_coeffs bond_coeffs angle_coeffs "
                                        "special_bonds fixes")
LammpsInput.__doc__ = """A LAMMPS input script read back (read_lammps_input).

header: the leading comment lines; commands: [(command, [arguments])] in order; pair_style:
its arguments; pair_coeffs: {(I, J): [floats]}; bond_coeffs, angle_coeffs: {type: [arguments]},
numbers as floats and words (a hybrid style's name, a table file and keyword) as strings;
special_bonds: its arguments; fixes: {fix id: [group, style, arguments...]}."""

# The integrators with a DPD friction (not Lowe's collision rate) that LAMMPS has no scheme of:
# an explicit approximate=True writes velocity Verlet with pair dpd for them, and says so.
_VERLET_LIKE = (DPDVVIntegrator, EDPDIntegrator, DenOtterClarkeIntegrator)

_Model = namedtuple("_Model", "masses soft thermostat bonds angles exclusions exceptions momentum custom")
# One pair_coeff of LAMMPS atom types I <= J: a, gamma (amu/ps) and the weight exponent s along e,
# the cutoff, and transverse friction's gamma (0: none) and exponent.
_PairRow = namedtuple("_PairRow", "i j a gamma s rc gamma_perp s_perp")


# --- Reading the System --------------------------------------------------------------------

def _value(quantity, target):
    return float(quantity.value_in_unit(target)) if unit.is_quantity(quantity) else float(quantity)


class _PairTable:
    """A type-pair table (soft repulsion or thermostat): values for a pair of types, either order."""

    def __init__(self, types, default, pairs):
        self.types, self.default, self.pairs = types, default, pairs

    def __call__(self, type1, type2):
        return self.pairs.get((min(type1, type2), max(type1, type2)), self.default)


def _soft_table(force, num_particles):
    rate = unit.kilojoule_per_mole / unit.nanometer
    pairs = {}
    for index in range(force.getNumTypePairs()):
        t1, t2, a, cutoff = force.getTypePairParameters(index)
        pairs[(min(t1, t2), max(t1, t2))] = (_value(a, rate), _value(cutoff, unit.nanometer))
    default = (_value(force.getDefaultA(), rate), _value(force.getDefaultCutoff(), unit.nanometer))
    return _PairTable([force.getParticleType(i) for i in range(num_particles)], default, pairs)


def _thermostat_table(integrator, num_particles):
    """(friction 1/ps, cutoff nm, weight exponent s, transverse friction 1/ps, its exponent) per pair of thermostat types."""
    rate = unit.picosecond**-1
    pairs = {}
    for index in range(integrator.getNumTypePairs()):
        t1, t2, friction, cutoff = integrator.getTypePairParameters(index)
        friction_perp, s_perp = integrator.getTypePairTransverseFriction(index)
        pairs[(min(t1, t2), max(t1, t2))] = (_value(friction, rate), _value(cutoff, unit.nanometer),
                                             float(integrator.getTypePairWeightExponent(index)), _value(friction_perp, rate),
                                             float(s_perp))
    default = (_value(integrator.getDefaultFriction(), rate), _value(integrator.getDefaultCutoff(), unit.nanometer),
               float(integrator.getDefaultWeightExponent()), _value(integrator.getDefaultTransverseFriction(), rate),
               float(integrator.getDefaultTransverseWeightExponent()))
    return _PairTable([integrator.getParticleType(i) for i in range(num_particles)], default, pairs)


def _describe(force):
    name = force.getName()
    kind = type(force).__name__
    return f"{kind} {name!r}" if name and name != kind else kind


def _harmonic_bonds(force):
    """[(i, j, "harmonic", K = k/2, r0)]."""
    bonds = []
    for index in range(force.getNumBonds()):
        i, j, length, k = force.getBondParameters(index)
        bonds.append((i, j, "harmonic", _value(k, unit.kilojoule_per_mole / unit.nanometer**2) / 2,
                      _value(length, unit.nanometer)))
    return bonds


def _custom_bonds(force, force_index):
    """[(i, j, "table", the force's index in the System, its per-bond parameters)]."""
    bonds = []
    for index in range(force.getNumBonds()):
        i, j, parameters = force.getBondParameters(index)
        bonds.append((i, j, "table", force_index, tuple(float(p) for p in parameters)))
    return bonds


def _harmonic_angles(force):
    """[(i, j, k, "harmonic", K = k/2, theta0 in degrees)]."""
    angles = []
    for index in range(force.getNumAngles()):
        i, j, k, theta0, stiffness = force.getAngleParameters(index)
        angles.append((i, j, k, "harmonic", _value(stiffness, unit.kilojoule_per_mole / unit.radian**2) / 2,
                       math.degrees(_value(theta0, unit.radian))))
    return angles


def _custom_angles(force, force_index):
    """[(i, j, k, "table", the force's index in the System, its per-angle parameters)]."""
    angles = []
    for index in range(force.getNumAngles()):
        i, j, k, parameters = force.getAngleParameters(index)
        angles.append((i, j, k, "table", force_index, tuple(float(p) for p in parameters)))
    return angles


def _soft_force(force, num_particles, found):
    if found["soft"] is not None:
        raise ValueError(f"export_lammps: the System has two DPDSoftRepulsionForces ({_describe(found['soft'][0])} "
                         f"and {_describe(force)}); LAMMPS's pair dpd takes one a per pair of types")
    if force.getNonbondedMethod() != DPDSoftRepulsionForce.CutoffPeriodic:
        raise ValueError(f"export_lammps: {_describe(force)} is not periodic (CutoffNonPeriodic); "
                         f"the script writes a periodic box (boundary p p p)")
    exclusions = {tuple(sorted(force.getExclusionParticles(k))) for k in range(force.getNumExclusions())}
    found["soft"] = (force, _soft_table(force, num_particles), exclusions)


def _is_empty(force):
    """A bonded Force with no terms adds nothing (the scenes' periodic marker is one)."""
    counts = {openmm.CustomBondForce: "getNumBonds", openmm.CustomAngleForce: "getNumAngles",
              openmm.HarmonicBondForce: "getNumBonds", openmm.HarmonicAngleForce: "getNumAngles"}
    method = counts.get(type(force))
    return method is not None and getattr(force, method)() == 0


def _read_forces(system, integrator):
    n = system.getNumParticles()
    found = {"soft": None, "bonds": [], "angles": [], "momentum": None, "custom": {}}
    groups = integrator.getIntegrationForceGroups()
    for force_index, force in enumerate(system.getForces()):
        if not groups & (1 << force.getForceGroup()):
            raise ValueError(f"export_lammps: {_describe(force)} is in force group {force.getForceGroup()}, which "
                             f"the integrator does not integrate; LAMMPS would apply it")
        if isinstance(force, DPDSoftRepulsionForce):
            _soft_force(force, n, found)
        elif type(force) is openmm.HarmonicBondForce:
            found["bonds"] += _harmonic_bonds(force)
        elif type(force) is openmm.CustomBondForce and force.getNumBonds():
            found["bonds"] += _custom_bonds(force, force_index)
            found["custom"][force_index] = force
        elif type(force) is openmm.HarmonicAngleForce:
            found["angles"] += _harmonic_angles(force)
        elif type(force) is openmm.CustomAngleForce and force.getNumAngles():
            found["angles"] += _custom_angles(force, force_index)
            found["custom"][force_index] = force
        elif type(force) is openmm.CMMotionRemover:
            found["momentum"] = force.getFrequency()
        elif not _is_empty(force):
            raise ValueError(f"export_lammps: {_describe(force)} has no LAMMPS equivalent here; exported are "
                             f"DPDSoftRepulsionForce, HarmonicBondForce, CustomBondForce, HarmonicAngleForce, "
                             f"CustomAngleForce and CMMotionRemover")
    return found


def _check_particles(system):
    if system.getNumParticles() == 0:
        raise ValueError("export_lammps: the System has no particles")
    if system.getNumConstraints():
        raise ValueError(f"export_lammps: the System has {system.getNumConstraints()} constraints; "
                         f"constraints are not exported")
    for i in range(system.getNumParticles()):
        if system.isVirtualSite(i) or _value(system.getParticleMass(i), unit.dalton) <= 0:
            raise ValueError(f"export_lammps: particle {i} is massless or a virtual site; every LAMMPS atom "
                             f"needs a mass > 0")
    if not system.usesPeriodicBoundaryConditions():
        raise ValueError("export_lammps: the System is not periodic; the script writes a periodic box")


def _read_model(system, integrator):
    _check_particles(system)
    n = system.getNumParticles()
    found = _read_forces(system, integrator)
    soft, exclusions = (None, set()) if found["soft"] is None else found["soft"][1:]
    exceptions = {}
    for index in range(integrator.getNumThermostatExceptions()):
        i, j, factor = integrator.getThermostatExceptionParameters(index)
        exceptions[(min(i, j), max(i, j))] = float(factor)
    masses = np.array([_value(system.getParticleMass(i), unit.dalton) for i in range(n)])
    return _Model(masses, soft, _thermostat_table(integrator, n), found["bonds"], found["angles"], exclusions,
                  exceptions, found["momentum"], found["custom"])


# --- The integrator ------------------------------------------------------------------------

def _integrator_name(integrator):
    name = type(integrator).__name__
    if isinstance(integrator, DPDVVIntegrator):
        variant = {DPDVVIntegrator.GrootWarren: f"GrootWarren, lambda {integrator.getLambda()!r}",
                   DPDVVIntegrator.DPDVV: "DPDVV", DPDVVIntegrator.SelfConsistent: "SelfConsistent"}
        return f"{name} ({variant[integrator.getVariant()]})"
    if isinstance(integrator, ShardlowIntegrator):
        return f"{name} (order {integrator.getOrder()})"
    if isinstance(integrator, LoweAndersenIntegrator):
        method = "Lowe" if integrator.getMethod() == LoweAndersenIntegrator.Lowe else "PairOrnsteinUhlenbeck"
        return f"{name} ({method})"
    if isinstance(integrator, StaggeredDPDIntegrator):
        base = "VelocityVerlet" if integrator.getBaseScheme() == StaggeredDPDIntegrator.VelocityVerlet else \
            "LoweAndersen"
        return f"{name} ({base} base, {integrator.getNumSubSteps()} sub-steps)"
    return name


def _exact_scheme(integrator):
    """'verlet', 'shardlow', or None where LAMMPS has no scheme of this integrator."""
    if isinstance(integrator, DPDVVIntegrator) and integrator.getVariant() == DPDVVIntegrator.GrootWarren \
            and integrator.getLambda() == 0.5:
        return "verlet"
    if isinstance(integrator, ShardlowIntegrator) and integrator.getOrder() == 1:
        return "shardlow"
    return None


def _closest_scheme(integrator):
    """The scheme approximate=True writes, or None where the friction means something else."""
    if isinstance(integrator, ShardlowIntegrator):
        return "shardlow"
    if isinstance(integrator, _VERLET_LIKE):
        return "verlet"
    if isinstance(integrator, LoweAndersenIntegrator) and integrator.getMethod() != LoweAndersenIntegrator.Lowe:
        return "verlet"
    if isinstance(integrator, StaggeredDPDIntegrator) and \
            integrator.getBaseScheme() == StaggeredDPDIntegrator.VelocityVerlet:
        return "verlet"
    return None


_SCHEMES = {"verlet": "fix nve with pair dpd (velocity Verlet, GrootWarren lambda 1/2)",
            "shardlow": "fix shardlow + fix nve with pair dpd/fdt (Shardlow S1)"}


def _scheme(integrator, approximate):
    """(scheme, warning or None)."""
    if not isinstance(integrator, DPDThermostatIntegrator):
        raise ValueError(f"export_lammps: {type(integrator).__name__} is not a DPD integrator of openmmdpd; "
                         f"give DPDVVIntegrator (GrootWarren, lambda 0.5) or ShardlowIntegrator (order 1)")
    name = _integrator_name(integrator)
    exact = _exact_scheme(integrator)
    if exact is not None:
        return exact, None
    closest = _closest_scheme(integrator)
    if closest is None:
        raise ValueError(f"export_lammps: {name} has no LAMMPS equivalent (its friction parameters are collision "
                         f"rates); export DPDVVIntegrator (GrootWarren, lambda 0.5) or ShardlowIntegrator (order 1)")
    if not approximate:
        raise ValueError(f"export_lammps: {name} has no LAMMPS equivalent; LAMMPS has velocity Verlet "
                         f"(DPDVVIntegrator GrootWarren, lambda 0.5) and Shardlow S1 (ShardlowIntegrator order 1). "
                         f"Pass approximate=True to write the closest, {_SCHEMES[closest]}, with a warning")
    return closest, f"WARNING: approximate: {name} is written as {_SCHEMES[closest]}, another scheme"


# --- Atom types and pair coefficients ------------------------------------------------------

def _atom_types(model):
    """(the distinct (soft type, thermostat type, mass), sorted; each particle's LAMMPS type from 1)."""
    soft = model.soft.types if model.soft is not None else [0] * len(model.masses)
    keys = [(soft[i], model.thermostat.types[i], float(model.masses[i])) for i in range(len(model.masses))]
    distinct = sorted(set(keys))
    number = {key: index + 1 for index, key in enumerate(distinct)}
    return distinct, np.array([number[key] for key in keys])


def _pair_cutoff(a, soft_cutoff, gamma, thermostat_cutoff, where):
    """LAMMPS's one cutoff of a pair: the soft force's and the thermostat's must agree where both act."""
    if soft_cutoff is None or a == 0:
        return thermostat_cutoff
    if gamma == 0 or math.isclose(soft_cutoff, thermostat_cutoff, rel_tol=1e-12):
        return soft_cutoff
    raise ValueError(f"export_lammps: {where} has the soft-repulsion cutoff {soft_cutoff!r} nm and the thermostat "
                     f"cutoff {thermostat_cutoff!r} nm; LAMMPS's pair dpd has one cutoff per pair of types")


def _pair_coefficients(model, distinct):
    """[_PairRow] for every pair of LAMMPS types I <= J."""
    rows = []
    for first in range(len(distinct)):
        for second in range(first, len(distinct)):
            (s1, t1, m1), (s2, t2, m2) = distinct[first], distinct[second]
            a, soft_cutoff = model.soft(s1, s2) if model.soft is not None else (0.0, None)
            friction, cutoff, exponent, friction_perp, exponent_perp = model.thermostat(t1, t2)
            two_mu = 2 * m1 * m2 / (m1 + m2)
            gamma = two_mu * friction
            where = (f"the pair of soft-repulsion types ({s1}, {s2}) with thermostat types ({t1}, {t2})")
            rows.append(_PairRow(first + 1, second + 1, a, gamma, exponent, _pair_cutoff(a, soft_cutoff, gamma, cutoff, where),
                                 two_mu * friction_perp, exponent_perp))
    return rows


# --- special_bonds ---------------------------------------------------------------------------

def _bond_distances(num_particles, bonds):
    """{(i, j), i < j: 1, 2 or 3} for the pairs 1, 2 or 3 bonds apart (the shortest path), as
    LAMMPS's special lists class them."""
    neighbours = [set() for _ in range(num_particles)]
    for i, j, *_ in bonds:
        neighbours[i].add(j)
        neighbours[j].add(i)
    distances = {}
    for start in {i for bond in bonds for i in bond[:2]}:
        seen, shell = {start}, {start}
        for distance in (1, 2, 3):
            shell = {k for i in shell for k in neighbours[i]} - seen
            seen |= shell
            for k in shell:
                distances[(min(start, k), max(start, k))] = distance
    return distances


def _pair_factor(model, pair):
    """The one factor LAMMPS must scale a pair by: its thermostat factor, which the soft force must match."""
    thermostat = model.exceptions.get(pair, 1.0)
    if model.soft is None or model.soft(model.soft.types[pair[0]], model.soft.types[pair[1]])[0] == 0:
        return thermostat
    conservative = 0.0 if pair in model.exclusions else 1.0
    if conservative != thermostat:
        raise ValueError(f"export_lammps: particles {pair[0]} and {pair[1]} have the soft-repulsion factor "
                         f"{conservative} ({'excluded' if conservative == 0 else 'not excluded'}) and the "
                         f"thermostat factor {thermostat}; LAMMPS's special_bonds scale both by one factor")
    return thermostat


def _special_factors(model):
    """(f12, f13, f14) for special_bonds lj; refuses what one factor per class cannot say."""
    distances = _bond_distances(len(model.masses), model.bonds)
    factors = {1: {}, 2: {}, 3: {}}
    for pair in set(distances) | model.exclusions | set(model.exceptions):
        factor = _pair_factor(model, pair)
        distance = distances.get(pair)
        if distance is None:
            if factor != 1.0:
                raise ValueError(f"export_lammps: particles {pair[0]} and {pair[1]} have the factor {factor} but "
                                 f"are not 1, 2 or 3 bonds apart; LAMMPS's special_bonds scale only those")
            continue
        factors[distance].setdefault(factor, pair)
    for distance, found in factors.items():
        if len(found) > 1:
            (f1, p1), (f2, p2) = sorted(found.items())[:2]
            raise ValueError(f"export_lammps: pairs {distance} bonds apart have different factors ({p1}: {f1}, "
                             f"{p2}: {f2}); LAMMPS's special_bonds take one factor per class")
    return tuple(next(iter(factors[d])) if factors[d] else 1.0 for d in (1, 2, 3))


# --- Box, positions, velocities ------------------------------------------------------------

def _array(values, target, name, num_particles):
    if unit.is_quantity(values):
        values = values.value_in_unit(target)
    values = [[_value(x, target) for x in row] if not unit.is_quantity(row) else list(row.value_in_unit(target))
              for row in values]
    array = np.asarray(values, dtype=float)
    if array.shape != (num_particles, 3) or not np.all(np.isfinite(array)):
        raise ValueError(f"export_lammps: {name} must be {num_particles} finite 3-vectors, got shape {array.shape}")
    return array


def _source(positions, velocities, box_vectors, system):
    """(positions, velocities or None, box vectors) from a Context, a State or plain arguments."""
    if isinstance(positions, openmm.Context):
        positions = positions.getState(getPositions=True, getVelocities=True)
    if isinstance(positions, openmm.State):
        state = positions
        positions = state.getPositions()
        if velocities is None:
            velocities = state.getVelocities()
        if box_vectors is None:
            box_vectors = state.getPeriodicBoxVectors()
    if box_vectors is None:
        box_vectors = system.getDefaultPeriodicBoxVectors()
    n = system.getNumParticles()
    box = _array(box_vectors, unit.nanometer, "box_vectors", 3)
    return (_array(positions, unit.nanometer, "positions", n),
            None if velocities is None else _array(velocities, unit.nanometer / unit.picosecond, "velocities", n),
            box)


def _check_box(box, shear_rate, scheme):
    if box[0, 1] or box[0, 2] or box[1, 2] or min(box[0, 0], box[1, 1], box[2, 2]) <= 0:
        raise ValueError(f"export_lammps: the box vectors {box.tolist()} are not in OpenMM's reduced form "
                         f"(a along x, b in the xy plane, positive lengths)")
    if abs(box[1, 0]) > box[0, 0] / 2 or abs(box[2, 0]) > box[0, 0] / 2 or abs(box[2, 1]) > box[1, 1] / 2:
        raise ValueError(f"export_lammps: the box's tilt {box.tolist()} exceeds half a box length; reduce it as "
                         f"OpenMM does (LAMMPS requires |xy|, |xz| <= Lx/2, |yz| <= Ly/2)")
    triclinic = bool(box[1, 0] or box[2, 0] or box[2, 1] or shear_rate)
    if shear_rate and (box[2, 0] or box[2, 1]):
        raise ValueError("export_lammps: a sheared box must have c = (0, 0, Lz)")
    if scheme == "shardlow" and triclinic:
        raise ValueError("export_lammps: LAMMPS's fix shardlow supports only orthogonal boxes; this box is "
                         "triclinic (tilted, or sheared)")
    return triclinic


def _wrap(positions, box):
    """(positions inside the box, image flags) with positions = wrapped + images @ box."""
    fractions = np.linalg.solve(box.T, positions.T).T
    images = np.floor(fractions)
    return positions - images @ box, images.astype(int)


def _molecules(num_particles, bonds, angles):
    """Molecule ids from 1 for the connected parts of the bond graph; 0 for unbonded atoms."""
    parent = list(range(num_particles))

    def root(i):
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i
    for term in [b[:2] for b in bonds] + [a[:3] for a in angles]:
        for other in term[1:]:
            parent[root(other)] = root(term[0])
    bonded = sorted({i for term in [b[:2] for b in bonds] + [a[:3] for a in angles] for i in term})
    ids, molecules = {}, np.zeros(num_particles, dtype=int)
    for i in bonded:
        molecules[i] = ids.setdefault(root(i), len(ids) + 1)
    return molecules


# --- Writing -------------------------------------------------------------------------------

def _number(x):
    """A float as text that reads back to the same double."""
    return repr(float(x))


def _term_types(parameters):
    """(each term's type from 1, [the distinct parameter tuples]) for bonds or angles."""
    distinct = sorted(set(parameters))
    number = {p: index + 1 for index, p in enumerate(distinct)}
    return [number[p] for p in parameters], distinct


def _type_names(topology, types):
    """{LAMMPS type: ", " + the topology's atom names of that type} for the Masses comments."""
    names = {}
    for atom, number in zip(topology.atoms(), types) if topology is not None else ():
        names.setdefault(number, set()).add(atom.name)
    return {number: ", atoms " + " ".join(sorted(found)[:4]) + (" ..." if len(found) > 4 else "")
            for number, found in names.items()}


def _data_header(model, distinct, names, bond_types, angle_types, box, triclinic):
    lines = ["LAMMPS data file written by openmmdpd.lammps.export_lammps", "",
             f"{len(model.masses)} atoms", f"{len(distinct)} atom types"]
    lines += [f"{len(model.bonds)} bonds", f"{len(bond_types)} bond types"]
    if model.angles:
        lines += [f"{len(model.angles)} angles", f"{len(angle_types)} angle types"]
    lines += ["", f"0.0 {_number(box[0, 0])} xlo xhi", f"0.0 {_number(box[1, 1])} ylo yhi",
              f"0.0 {_number(box[2, 2])} zlo zhi"]
    if triclinic:
        lines.append(f"{_number(box[1, 0])} {_number(box[2, 0])} {_number(box[2, 1])} xy xz yz")
    lines += ["", "Masses", ""]
    lines += [f"{t} {_number(mass)}  # soft-repulsion type {soft}, thermostat type {thermostat}{names.get(t, '')}"
              for t, (soft, thermostat, mass) in enumerate(distinct, 1)]
    return lines


def _lammps_flow_frame(velocities, rate, box):
    """Velocities in the frame of LAMMPS's imposed flow, rate (y - ylo) along x with ylo = 0, from
    openmm-dpd's, rate (y - Ly/2): shifted by rate Ly/2 along x. The shift changes no relative
    velocity, so no force; it makes compute temp/deform, which removes rate (y - ylo), see the
    peculiar velocities."""
    shifted = np.array(velocities, dtype=float)
    shifted[:, 0] += rate * box[1, 1] / 2
    return shifted


def _data_file(model, distinct, types, names, box, triclinic, positions, velocities):
    bond_numbers, bond_types = _term_types([b[2:] for b in model.bonds])
    angle_numbers, angle_types = _term_types([a[3:] for a in model.angles])
    lines = _data_header(model, distinct, names, bond_types, angle_types, box, triclinic)
    wrapped, images = _wrap(positions, box)
    molecules = _molecules(len(types), model.bonds, model.angles)
    lines += ["", f"Atoms  # {'molecular' if model.angles else 'bond'}", ""]
    lines += [f"{i + 1} {molecules[i]} {types[i]} {' '.join(map(_number, wrapped[i]))} {' '.join(map(str, images[i]))}"
              for i in range(len(types))]
    if velocities is not None:
        lines += ["", "Velocities", ""]
        lines += [f"{i + 1} {' '.join(map(_number, v))}" for i, v in enumerate(velocities)]
    if model.bonds:
        lines += ["", "Bonds", ""]
        lines += [f"{k + 1} {t} {b[0] + 1} {b[1] + 1}" for k, (t, b) in enumerate(zip(bond_numbers, model.bonds))]
    if model.angles:
        lines += ["", "Angles", ""]
        lines += [f"{k + 1} {t} {a[0] + 1} {a[1] + 1} {a[2] + 1}"
                  for k, (t, a) in enumerate(zip(angle_numbers, model.angles))]
    return "\n".join(lines) + "\n", bond_types, angle_types


def _pair_lines(scheme, rows, kT, seed):
    """pair_style and pair_coeff: dpd (a gamma rc), dpd/ext (a gamma gamma_perp ws ws_perp rc) or dpd/fdt (a sigma rc)."""
    global_cutoff = _number(max(row.rc for row in rows))
    if scheme == "shardlow":
        # dpd/fdt skips every conservative force when its last pair_coeff has a = 0: end on a nonzero a.
        rows = sorted(rows, key=lambda row: row.a != 0)
        lines = [f"pair_style dpd/fdt {_number(kT)} {global_cutoff} {seed}"]
        return lines + [f"pair_coeff {r.i} {r.j} {_number(r.a)} {_number(math.sqrt(2 * kT * r.gamma))} {_number(r.rc)}"
                        for r in rows]
    if all(row.s == 2.0 and row.gamma_perp == 0 for row in rows):
        lines = [f"pair_style dpd {_number(kT)} {global_cutoff} {seed}"]
        return lines + [f"pair_coeff {r.i} {r.j} {_number(r.a)} {_number(r.gamma)} {_number(r.rc)}" for r in rows]
    lines = [f"pair_style dpd/ext {_number(kT)} {global_cutoff} {seed}"]
    return lines + [f"pair_coeff {r.i} {r.j} {_number(r.a)} {_number(r.gamma)} {_number(r.gamma_perp)} {_number(r.s / 2)} "
                    f"{_number(r.s_perp / 2)} {_number(r.rc)}" for r in rows]


def _half_width(box):
    """Half the shortest distance between opposite faces of the box: the longest nearest-image distance
    along the narrowest direction."""
    volume = abs(np.linalg.det(box))
    return min(volume / np.linalg.norm(np.cross(box[(k + 1) % 3], box[(k + 2) % 3])) for k in range(3)) / 2


def _tables(model, term_types, tabulate):
    """{type number: Table} for the tabulated types among term_types (bonds or angles);
    tabulate(force, parameters, where) makes one."""
    tables = {}
    for number, (style, *parameters) in enumerate(term_types, 1):
        if style == "table":
            force_index, values = parameters
            force = model.custom[force_index]
            tables[number] = tabulate(force, values, f"{_describe(force)} (force {force_index}) with parameters "
                                                     f"{list(values)}")
    return tables


def _bond_reach(bond_types, tables, angle_types, kT):
    """The longest distance between atoms of one bonded term: a harmonic bond (K = k/2 here) stays
    within BOND_ENERGY_LIMIT kT of its minimum, r0 + sqrt(BOND_ENERGY_LIMIT kT / K); a tabulated
    one within its table; an angle's ends are two bonds apart. Bonds with K = 0 exert no force and
    are not counted."""
    harmonic = [r0 + math.sqrt(BOND_ENERGY_LIMIT * kT / K) for style, *p in bond_types if style == "harmonic"
                for K, r0 in [p] if K > 0]
    bond = max(harmonic + [table.reach for table in tables.values()], default=0.0)
    return 2 * bond if angle_types else bond


def _ghost_cutoff(rows, bond_types, tables, angle_types, kT):
    """The ghost-atom cutoff `comm_modify cutoff` must set, or None where LAMMPS's default (the pair
    cutoff + skin) already holds every bonded partner. LAMMPS finds a bond's partner among its
    ghost atoms: a bond that stretches past the ghost cutoff across the box's edge would act on a
    far image of its partner. DPD's rest-length-0 springs (k 4, kT 1) stretch past r_c + skin on a
    few percent of the bonds at any time."""
    reach = math.ceil(round(100 * (_bond_reach(bond_types, tables, angle_types, kT) + SKIN), 6)) / 100
    return reach if reach > max(row.rc for row in rows) + SKIN else None


def _header(integrator, scheme, warning, kT, factors):
    lines = ["# A DPD model exported by openmmdpd.lammps.export_lammps from an OpenMM System.",
             "# Units: LAMMPS lj with sigma = 1 nm, m = 1 amu (g/mol), epsilon = 1 kJ/mol, so tau = 1 ps;",
             "#   forces in kJ/mol/nm, friction gamma in amu/ps, and the lj temperature T* = kT / (1 kJ/mol)",
             f"#   = {_number(kT)} (OpenMM temperature {_number(_value(integrator.getTemperature(), unit.kelvin))} K).",
             f"# Integrator: {_integrator_name(integrator)} -> {_SCHEMES[scheme]}."]
    if scheme == "verlet":
        lines.append("#   fix nve evaluates pair dpd with the velocities after its first half kick: lambda = 1/2.")
    if any(0 < f < 1 for f in factors):
        lines.append("# special_bonds factors between 0 and 1 keep fluctuation-dissipation only where LAMMPS's pair "
                     "dpd scales the random force by sqrt(factor), as its current sources do.")
    if warning:
        lines.append(f"# {warning}")
    return lines


def _communication_lines(plan):
    """comm_modify: ghost velocities (pair dpd needs them) and, where bonds reach past the pair
    cutoff + skin, a ghost cutoff that holds every bonded partner."""
    ghost_cutoff = _ghost_cutoff(plan.rows, plan.bond_types, plan.bond_tables, plan.angle_types, plan.kT)
    if ghost_cutoff is None:
        return [], "comm_modify vel yes"
    note = (f"# Ghost atoms out to {_number(ghost_cutoff)}: the longest bonded distance expected at this kT "
            f"(a bond's energy {_number(BOND_ENERGY_LIMIT)} kT above its minimum) plus the skin, so that a "
            f"stretched bond across the box's edge finds its partner's nearest image.")
    return [note], f"comm_modify vel yes cutoff {_number(ghost_cutoff)}"


def _term_lines(kind, term_types, table_name, points):
    """{kind}_style and {kind}_coeff (kind bond or angle): harmonic, table, or both (hybrid)."""
    styles = {style for style, *_ in term_types}
    table_style = f"table linear {points}"
    named = len(styles) > 1
    lines = ["", f"{kind}_style " + ("hybrid harmonic " + table_style if named else
                                     "harmonic" if styles == {"harmonic"} else table_style)]
    for number, (style, *parameters) in enumerate(term_types, 1):
        label = f"{style} " if named else ""
        if style == "harmonic":
            lines.append(f"{kind}_coeff {number} {label}{' '.join(map(_number, parameters))}")
        else:
            lines.append(f"{kind}_coeff {number} {label}{table_name} {_table_keyword(kind, number)}")
    return lines


def _table_keyword(kind, number):
    return f"{kind.upper()}_{number}"


def _input_script(integrator, model, plan, names, steps):
    lines = _header(integrator, plan.scheme, plan.warning, plan.kT, plan.factors)
    if plan.shear and plan.has_velocities:
        lines.append(f"# Velocities are in the frame of fix deform's flow, rate (y - ylo) along x: openmm-dpd's, "
                     f"rate (y - Ly/2), plus rate Ly/2 = {_number(plan.shear * plan.box_height / 2)}.")
    if plan.shear and abs(plan.drift) > 1e-12:
        lines.append(f"# WARNING: the centre of mass moves at {plan.drift!r} along y. Under shear that moves it along "
                     f"x at -rate times that per unit time, which compute temp/deform counts as heat and as P_xy "
                     f"(it removes only the imposed flow); start a NEMD run without it (velocity all zero linear).")
    notes, communicate = _communication_lines(plan)
    lines += notes
    lines += ["", "units lj", f"atom_style {'molecular' if model.angles else 'bond'}", "boundary p p p",
              "newton on", communicate, f"read_data {names.data}", ""]
    lines += _pair_lines(plan.scheme, plan.rows, plan.kT, plan.seed)
    if plan.bond_types:
        lines += _term_lines("bond", plan.bond_types, names.table, TABLE_POINTS)
    if plan.angle_types:
        lines += _term_lines("angle", plan.angle_types, names.table, ANGLE_POINTS)
    lines += ["", f"special_bonds lj {' '.join(map(_number, plan.factors))}",
              f"neighbor {_number(SKIN)} bin", "neigh_modify every 1 delay 0 check yes", "",
              f"timestep {_number(_value(integrator.getStepSize(), unit.picosecond))}"]
    lines += _fix_lines(plan, model)
    lines += ["", "thermo_style custom step temp press pe ke", "thermo 100"]
    if plan.shear:  # temperature and pressure of the peculiar velocities, as openmm-dpd's pressure tensor
        lines += ["compute peculiar all temp/deform", "thermo_modify temp peculiar"]
    lines.append(f"run {steps}")
    return "\n".join(lines) + "\n"


def _fix_lines(plan, model):
    lines = []
    if not plan.has_velocities:
        lines.append(f"velocity all create {_number(plan.kT)} {plan.seed} dist gaussian mom yes")
    if plan.scheme == "shardlow":
        lines.append("fix shardlow all shardlow")
    lines.append("fix integrate all nve")
    if plan.shear:
        lines.append(f"fix shear all deform 1 xy erate {_number(plan.shear)} remap v flip yes")
    if model.momentum:
        lines.append(f"fix momentum all momentum {model.momentum} linear 1 1 1")
    return lines


def _seed(integrator, seed):
    seed = integrator.getRandomNumberSeed() if seed is None else seed
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or not 1 <= seed <= MAX_SEED:
        raise ValueError(f"export_lammps: seed must be an integer from 1 to {MAX_SEED} (LAMMPS's random number "
                         f"generator), got {seed!r}; the integrator's seed 0 (a new one per Context) has no "
                         f"LAMMPS equivalent: pass seed= or set one with setRandomNumberSeed")
    return int(seed)


_Plan = namedtuple("_Plan", "scheme warning kT seed distinct types rows factors triclinic shear "
                           "bond_types angle_types bond_tables has_velocities drift box_height")


def _plan(integrator, model, box, seed, approximate):
    """What the atom types, pair coefficients and fixes say, checked: the refusals about the
    integrator, the box and the pairs happen here, before any file."""
    scheme, warning = _scheme(integrator, approximate)
    shear = _value(integrator.getShearRate(), unit.picosecond**-1)
    triclinic = _check_box(box, shear, scheme)
    distinct, types = _atom_types(model)
    rows = _pair_coefficients(model, distinct)
    factors = _special_factors(model)
    if scheme == "shardlow":
        if any(row.s != 2.0 for row in rows):
            raise ValueError("export_lammps: LAMMPS's pair dpd/fdt has only the weight exponent 2; this "
                             "ShardlowIntegrator sets another (setDefaultWeightExponent, setTypePairWeightExponent)")
        if any(row.gamma_perp != 0 for row in rows):
            raise ValueError("export_lammps: LAMMPS's pair dpd/fdt has no transverse friction; this ShardlowIntegrator "
                             "sets one (setDefaultTransverseFriction, setTypePairTransverseFriction): export "
                             "DPDVVIntegrator (GrootWarren, lambda 0.5), which pair dpd/ext runs with it")
        if any(0 < f < 1 for f in factors):
            raise ValueError(f"export_lammps: LAMMPS's fix shardlow ignores special_bonds factors between 0 and 1; "
                             f"the factors here are {factors}")
    kT = kT_from_temperature(integrator.getTemperature())
    return _Plan(scheme, warning, kT, _seed(integrator, seed), distinct, types, rows, factors, triclinic, shear,
                 None, None, None, None, 0.0, float(box[1, 1]))


def export_lammps(system, integrator, positions, path, velocities=None, box_vectors=None, topology=None,
                  steps=0, seed=None, approximate=False):
    """Write a LAMMPS data file (path + ".data") and input script (path + ".in") that run this model,
    and a table file (path + ".table") where bonds or angles are tabulated.

    :param system: the OpenMM System: a DPDSoftRepulsionForce, HarmonicBondForce, CustomBondForce
        (tabulated: FENE, worm-like chains, any bond energy of r), HarmonicAngleForce,
        CustomAngleForce (tabulated) and CMMotionRemover are exported; any other Force is refused.
    :param integrator: DPDVVIntegrator (GrootWarren, lambda 0.5) or ShardlowIntegrator (order 1);
        others are refused unless approximate=True (then the closest scheme, with a warning in
        the script's header; Lowe-Andersen collisions are refused always).
    :param positions: positions (nm), or an OpenMM State or Context (then its positions,
        velocities and box vectors are used).
    :param path: the files' path without extension; the script reads the data file by its name,
        so run LAMMPS in that folder (``lmp -in model.in``).
    :param velocities: nm/ps; None: those of a State or Context if given, else the script draws
        them (``velocity all create``).
    :param box_vectors: the box (nm); default: the State's, else the System's default box.
    :param topology: optional; its atom names are noted beside each atom type's mass, and its
        number of atoms must be the System's.
    :param steps: the number of steps the script runs, >= 0.
    :param seed: the random seed, 1 to MAX_SEED; default: the integrator's (which must not be 0).
    :param approximate: write the closest scheme for an integrator LAMMPS has no equivalent of.
    :returns: LammpsFiles(data, input, table); table is None where nothing is tabulated. Nothing is
        written when anything is refused.
    """
    if topology is not None and topology.getNumAtoms() != system.getNumParticles():
        raise ValueError(f"export_lammps: the topology has {topology.getNumAtoms()} atoms, the System "
                         f"{system.getNumParticles()} particles")
    if isinstance(steps, bool) or not isinstance(steps, (int, np.integer)) or steps < 0:
        raise ValueError(f"export_lammps: steps must be an integer >= 0, got {steps!r}")
    model = _read_model(system, integrator)
    positions, velocities, box = _source(positions, velocities, box_vectors, system)
    plan = _plan(integrator, model, box, seed, approximate)
    drift = 0.0 if velocities is None else float(model.masses @ velocities[:, 1] / model.masses.sum())
    if velocities is not None and plan.shear:
        velocities = _lammps_flow_frame(velocities, plan.shear, box)
    data, bond_types, angle_types = _data_file(model, plan.distinct, plan.types, _type_names(topology, plan.types),
                                               box, plan.triclinic, positions, velocities)
    bond_tables = _tables(model, bond_types, lambda force, values, where:
                          tabulate_bond(force, values, plan.kT, _half_width(box), where))
    angle_tables = _tables(model, angle_types, tabulate_angle)
    plan = plan._replace(bond_types=bond_types, angle_types=angle_types, bond_tables=bond_tables,
                         has_velocities=velocities is not None, drift=drift)
    tables = {_table_keyword(kind, number): table for kind, found in (("bond", bond_tables), ("angle", angle_tables))
              for number, table in found.items()}
    files = LammpsFiles(os.fspath(path) + ".data", os.fspath(path) + ".in",
                        os.fspath(path) + ".table" if tables else None)
    names = LammpsFiles(*(None if name is None else os.path.basename(name) for name in files))
    texts = {files.data: data, files.input: _input_script(integrator, model, plan, names, int(steps))}
    if tables:
        texts[files.table] = table_text(tables)
    _write_all(texts)
    return files


def _write_all(texts):
    """Every file or none: {path: text}, each written beside its target, then moved into place."""
    temporary = {name: name + ".partial" for name in texts}
    try:
        for name, text in texts.items():
            with open(temporary[name], "w") as f:
                f.write(text)
        for name, partial in temporary.items():
            os.replace(partial, name)
    finally:
        for partial in temporary.values():
            if os.path.exists(partial):
                os.remove(partial)


# --- Reading back --------------------------------------------------------------------------

_SECTIONS = ("Masses", "Atoms", "Velocities", "Bonds", "Angles")


def _data_sections(path):
    """({header keyword: [numbers]}, {section: [rows of numbers]}) of a data file, comments removed."""
    with open(path) as f:
        lines = f.read().splitlines()[1:]  # the first line is a title
    header, sections, current = {}, {}, None
    for line in lines:
        words = line.split("#", 1)[0].split()
        if not words:
            continue
        if words[0] in _SECTIONS:
            current = sections.setdefault(words[0], [])
        elif current is not None:
            current.append([float(w) for w in words])
        else:
            numbers = [w for w in words if not w.isalpha()]
            header[" ".join(w for w in words if w.isalpha())] = [float(w) for w in numbers]
    return header, sections


def _rows(sections, name, width):
    rows = sorted(sections.get(name, []))
    return np.array(rows, dtype=float).reshape(-1, width)


def read_lammps_data(path):
    """Read a data file export_lammps wrote (atom style bond or molecular) into a LammpsData."""
    header, sections = _data_sections(path)
    atoms = _rows(sections, "Atoms", 9)
    velocities = _rows(sections, "Velocities", 4) if "Velocities" in sections else None
    xy, xz, yz = header.get("xy xz yz", [0.0, 0.0, 0.0])
    lengths = [header[f"{x}lo {x}hi"][1] - header[f"{x}lo {x}hi"][0] for x in "xyz"]
    box = np.array([[lengths[0], 0, 0], [xy, lengths[1], 0], [xz, yz, lengths[2]]])
    bonds, angles = _rows(sections, "Bonds", 4), _rows(sections, "Angles", 5)
    return LammpsData(masses={int(t): m for t, m in sections.get("Masses", [])},
                      types=atoms[:, 2].astype(int), molecules=atoms[:, 1].astype(int),
                      positions=atoms[:, 3:6], images=atoms[:, 6:9].astype(int),
                      velocities=None if velocities is None else velocities[:, 1:],
                      bonds=np.column_stack([bonds[:, 1], bonds[:, 2:] - 1]).astype(int),
                      angles=np.column_stack([angles[:, 1], angles[:, 2:] - 1]).astype(int), box=box)


def _number_or_word(text):
    try:
        return float(text)
    except ValueError:
        return text


def read_lammps_input(path):
    """Read an input script export_lammps wrote into a LammpsInput (commands and coefficients)."""
    with open(path) as f:
        lines = f.read().splitlines()
    header = []
    for line in lines:
        if not line.startswith("#"):
            break
        header.append(line[1:].strip())
    commands = [(words[0], words[1:]) for words in (line.split("#", 1)[0].split() for line in lines) if words]
    pair_style, special, coefficients, fixes = [], [], {"pair_coeff": {}, "bond_coeff": {}, "angle_coeff": {}}, {}
    for command, arguments in commands:
        if command == "pair_coeff":
            coefficients[command][(int(arguments[0]), int(arguments[1]))] = [float(x) for x in arguments[2:]]
        elif command in ("bond_coeff", "angle_coeff"):
            coefficients[command][int(arguments[0])] = [_number_or_word(x) for x in arguments[1:]]
        elif command == "pair_style":
            pair_style = arguments
        elif command == "special_bonds":
            special = arguments
        elif command == "fix":
            fixes[arguments[0]] = arguments[1:]
    return LammpsInput(header, commands, pair_style, coefficients["pair_coeff"], coefficients["bond_coeff"],
                       coefficients["angle_coeff"], special, fixes)
