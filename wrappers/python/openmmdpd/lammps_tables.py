"""Bond and angle potentials of any CustomBondForce (FENE, worm-like chains, ...) and
CustomAngleForce (cosine angles, ...) as LAMMPS `bond_style table` and `angle_style table`
sections, for openmmdpd.lammps (docs/guide/lammps.md).

OpenMM itself evaluates each term's energy and force on a grid (a System of two or three
particles on the Reference platform), so whatever the expression says is what LAMMPS reads: no
expression is parsed here. A bond's grid runs from 0 to the length where the energy first
exceeds its minimum by BOND_ENERGY_LIMIT kT, or stops being finite (FENE's and the worm-like
chain's maximum extension); LAMMPS stops with an error if a bond ever passes the table's end.
An angle's grid runs from 0 to 180 degrees, as LAMMPS requires.
"""
import numpy as np
import openmm
from openmm import unit

__all__ = ["BOND_ENERGY_LIMIT", "TABLE_POINTS", "ANGLE_POINTS", "Table", "tabulate_bond", "tabulate_angle",
           "table_text", "read_tables"]

#: A bond's energy above its minimum, in kT, taken never to be reached (Boltzmann weight e^-32,
#: about 1e-14): the end of a table, and for a harmonic bond r0 + 8 sqrt(kT/k).
BOND_ENERGY_LIMIT = 32.0

#: Lengths per bond table, written as LAMMPS interpolates (`bond_style table linear TABLE_POINTS`).
TABLE_POINTS = 2000

#: Angles per angle table, 0 to 180 degrees every 0.1 (`angle_style table linear ANGLE_POINTS`).
ANGLE_POINTS = 1801

_SCAN_STEP = 1e-3  # nm: the grid the table's end is searched on
_SMALLEST = 1e-6   # nm, or radians: the force at r = 0 (theta = 0, pi) is taken this far inside


class Table:
    """One term type's table: the coordinate (bond length in nm, or angle in degrees), the
    energies (kJ/mol) and the forces (-dE/dr in kJ/mol/nm, or -dE/dtheta per degree)."""

    def __init__(self, points, energies, forces):
        self.points, self.energies, self.forces = points, energies, forces

    @property
    def reach(self):
        """The longest bond a bond table covers."""
        return float(self.points[-1])


def _term_context(force, parameters, num_particles):
    """A Context of the particles of one term of `force`'s expression with these parameters."""
    if getattr(force, "getNumTabulatedFunctions", lambda: 0)():  # OpenMM 7.7's bonded Forces have none
        raise ValueError("uses tabulated functions, which are not exported")
    kind = "Bond" if num_particles == 2 else "Angle"
    term = getattr(openmm, f"Custom{kind}Force")(force.getEnergyFunction())
    for k in range(getattr(force, f"getNumPer{kind}Parameters")()):
        getattr(term, f"addPer{kind}Parameter")(getattr(force, f"getPer{kind}ParameterName")(k))
    for k in range(force.getNumGlobalParameters()):
        term.addGlobalParameter(force.getGlobalParameterName(k), force.getGlobalParameterDefaultValue(k))
    getattr(term, f"add{kind}")(*range(num_particles), list(parameters))
    system = openmm.System()
    for _ in range(num_particles):
        system.addParticle(1.0)
    system.addForce(term)
    return openmm.Context(system, openmm.VerletIntegrator(0.001), openmm.Platform.getPlatformByName("Reference"))


def _evaluate(context, lengths):
    """(energies, forces -dE/dr) of the bond at each length."""
    energies, forces = [], []
    for r in lengths:
        context.setPositions([openmm.Vec3(0, 0, 0), openmm.Vec3(max(r, _SMALLEST), 0, 0)])
        state = context.getState(getEnergy=True, getForces=True)
        energies.append(state.getPotentialEnergy().value_in_unit(unit.kilojoule_per_mole))
        forces.append(state.getForces()[1][0].value_in_unit(unit.kilojoule_per_mole / unit.nanometer))
    return np.array(energies), np.array(forces)


def _table_end(context, kT, longest, where):
    """The length at which the energy first exceeds its minimum so far by BOND_ENERGY_LIMIT kT or
    is no longer finite, searched out to `longest`."""
    lengths = np.arange(0.0, longest + _SCAN_STEP, _SCAN_STEP)
    energies, _ = _evaluate(context, lengths)
    with np.errstate(invalid="ignore"):
        past = ~np.isfinite(energies) | (energies - np.minimum.accumulate(np.nan_to_num(energies, nan=np.inf))
                                         > BOND_ENERGY_LIMIT * kT)
    if not past.any():
        raise ValueError(f"export_lammps: {where} stays within {BOND_ENERGY_LIMIT:g} kT of its minimum out to "
                         f"{longest:g} nm, half the box: LAMMPS measures a bond at its partner's nearest image, "
                         f"and a table must end before that")
    end = int(np.argmax(past))
    if end < 2:
        raise ValueError(f"export_lammps: {where} is not finite, or already {BOND_ENERGY_LIMIT:g} kT above its "
                         f"minimum, at lengths below {2 * _SCAN_STEP:g} nm")
    return float(lengths[end - 1])


def _context(force, parameters, num_particles, where):
    try:
        return _term_context(force, parameters, num_particles)
    except (ValueError, openmm.OpenMMException) as error:
        raise ValueError(f"export_lammps: {where} {error}") from None


def tabulate_bond(force, parameters, kT, longest, where):
    """The Table of one bond of a CustomBondForce with these per-bond parameters, at kT (kJ/mol),
    ending before `longest` (nm); `where` names the bond type in errors."""
    context = _context(force, parameters, 2, where)
    lengths = np.linspace(0.0, _table_end(context, kT, longest, where), TABLE_POINTS)
    energies, forces = _evaluate(context, lengths)
    if not (np.isfinite(energies).all() and np.isfinite(forces).all()):
        raise ValueError(f"export_lammps: {where} is not finite at every length from 0 to {lengths[-1]:g} nm")
    return Table(lengths, energies, forces)


def tabulate_angle(force, parameters, where):
    """The Table of one angle of a CustomAngleForce with these per-angle parameters, from 0 to 180
    degrees; the force is -dE/dtheta per degree, as LAMMPS reads it."""
    context = _context(force, parameters, 3, where)
    degrees = np.linspace(0.0, 180.0, ANGLE_POINTS)
    energies, forces = [], []
    for theta in np.clip(np.radians(degrees), _SMALLEST, np.pi - _SMALLEST):
        # The vertex at the origin, one end along x, the other at theta in the xy plane (unit arms).
        end = openmm.Vec3(np.cos(theta), np.sin(theta), 0)
        context.setPositions([openmm.Vec3(1, 0, 0), openmm.Vec3(0, 0, 0), end])
        state = context.getState(getEnergy=True, getForces=True)
        force_on_end = state.getForces(asNumpy=True)[2].value_in_unit(unit.kilojoule_per_mole / unit.nanometer)
        energies.append(state.getPotentialEnergy().value_in_unit(unit.kilojoule_per_mole))
        # The force on the end along increasing theta is -dE/dtheta over the arm's length 1.
        forces.append(float(np.dot(force_on_end, [-np.sin(theta), np.cos(theta), 0])) * np.pi / 180)
    energies, forces = np.array(energies), np.array(forces)
    if not (np.isfinite(energies).all() and np.isfinite(forces).all()):
        raise ValueError(f"export_lammps: {where} is not finite at every angle from 0 to 180 degrees")
    return Table(degrees, energies, forces)


def table_text(tables):
    """A LAMMPS table file with one section per {keyword: Table}."""
    lines = ["# Potentials tabulated by openmmdpd.lammps.export_lammps: index, r (or theta in degrees), energy, "
             "force -dE/dr (or -dE/dtheta per degree)"]
    for keyword, table in tables.items():
        lines += ["", keyword, f"N {len(table.points)}", ""]
        lines += [f"{k} {x!r} {e!r} {f!r}" for k, (x, e, f) in
                  enumerate(zip(table.points.tolist(), table.energies.tolist(), table.forces.tolist()), 1)]
    return "\n".join(lines) + "\n"


def read_tables(path):
    """{keyword: Table} of a table file table_text wrote."""
    with open(path) as f:
        blocks = [block.strip().splitlines() for block in f.read().split("\n\n")]
    tables, keyword = {}, None
    for block in blocks:
        if len(block) == 2 and block[1].startswith("N "):
            keyword = block[0]
        elif keyword is not None and block:
            rows = np.array([[float(w) for w in line.split()] for line in block])
            tables[keyword] = Table(rows[:, 1], rows[:, 2], rows[:, 3])
            keyword = None
    return tables
