"""Smeared-charge electrostatics for charged DPD beads, from OpenMM's own forces.

Point charges on soft DPD beads collapse into pairs: nothing keeps two opposite charges
apart, and q_i q_j / r diverges.  Spreading each charge over a cloud of size lambda makes the
pair energy finite at r = 0 and leaves it Coulomb's law at r >> lambda.  The long-ranged
part is the point-charge interaction, which OpenMM's NonbondedForce sums with PME; the
difference smeared - point decays as fast as the clouds do and is a short-ranged
CustomNonbondedForce.  Both are ordinary OpenMM forces, so this works on every platform
that has PME.

Lengths are in units of the DPD cutoff r_c and energies in units of kT, both those of a
`DPDUnits` (by default r_c = 1 nm and kT = 1 kJ/mol).  The theory is in the documentation
(theory/electrostatics), the use in guide/charged-dpd.
"""
import math
import numbers
from dataclasses import dataclass

import numpy as np
import openmm
from openmm import unit

from .units import DPDUnits

__all__ = ["ONE_4PI_EPS0", "SMEARING_FORMS", "SmearedElectrostatics", "add_smeared_electrostatics",
           "fast_pme_grid", "smeared_pair_energy", "smeared_pair_limit", "correction_cutoff"]

#: 1/(4 pi eps0) in kJ/mol nm/e^2, computed as OpenMM computes it (SI 2019 constants).
ONE_4PI_EPS0 = 138.93545764438198

_WHERE = "add_smeared_electrostatics"


@dataclass(frozen=True)
class _Form:
    """A smearing: u(r) = l_B/r (1 - deficit(r)), in kT for two unit charges.

    `deficit` is the fraction of Coulomb's law that the clouds' overlap takes away (1 at r = 0,
    0 far away), `slope` its derivative in r, `expression` the deficit in OpenMM's expression
    language (r and the smearing length L in nm), and `limit` is u(0) L / l_B.
    """
    deficit: object
    slope: object
    expression: str
    limit: float


def _slater_deficit(r, length):
    return (1 + r / length) * math.exp(-2 * r / length)


def _slater_slope(r, length):
    return -(1 + 2 * r / length) * math.exp(-2 * r / length) / length


def _overlap_deficit(r, length):
    y = 2 * r / length
    return math.exp(-y) * (1 + 11 * y / 16 + 3 * y ** 2 / 16 + y ** 3 / 48)


def _overlap_slope(r, length):
    y = 2 * r / length
    return -2 / length * math.exp(-y) * (5 / 16 + 5 * y / 16 + y ** 2 / 8 + y ** 3 / 48)


def _gaussian_deficit(r, length):
    return math.erfc(r / (2 * length))


def _gaussian_slope(r, length):
    return -math.exp(-(r / (2 * length)) ** 2) / (length * math.sqrt(math.pi))


#: The smearing forms and their pair energies u(r) = l_B q_i q_j / r (1 - deficit(r)):
#: "slater", deficit (1 + r/lambda) exp(-2r/lambda), the energy of a point charge and an
#: exponential cloud exp(-2r/lambda) (Gonzalez-Melchor et al. 2006's pair form, with their
#: 1/beta as lambda); "slater-overlap", the exact energy of two such clouds; "gaussian",
#: deficit erfc(r/(2 sigma)), two Gaussian clouds of standard deviation sigma each.
SMEARING_FORMS = {
    "slater": _Form(_slater_deficit, _slater_slope, "(1 + r/L)*exp(-2*r/L)", 1.0),
    "slater-overlap": _Form(_overlap_deficit, _overlap_slope,
                            "exp(-y)*(1 + 11*y/16 + 3*y^2/16 + y^3/48); y = 2*r/L", 5 / 8),
    "gaussian": _Form(_gaussian_deficit, _gaussian_slope, "erfc(r/(2*L))", 1 / math.sqrt(math.pi)),
}


def smeared_pair_energy(r, form, smearing_length, bjerrum_length=1.0):
    """The smeared pair energy u(r) of two unit charges, in kT (float or array like `r`).

    :param r: the distance (>= 0), in units of r_c; a number or an array.
    :param form: a key of `SMEARING_FORMS`.
    :param smearing_length: lambda (or sigma for "gaussian"), in units of r_c; > 0.
    :param bjerrum_length: l_B in units of r_c; > 0.

    At r = 0 it is the finite limit `smeared_pair_limit`; for r >> lambda it is l_B / r.
    """
    where = "smeared_pair_energy"
    shape = _form(form, where)
    length = _positive(smearing_length, "smearing_length", where)
    bjerrum = _positive(bjerrum_length, "bjerrum_length", where)

    def one(x):
        if x == 0:
            return bjerrum * shape.limit / length
        return bjerrum * (1 - shape.deficit(x, length)) / x

    distances = np.asarray(r, dtype=float)
    if np.any(distances < 0) or not np.all(np.isfinite(distances)):
        raise ValueError(f"{where}: r must be finite and >= 0 (units of r_c), got {r!r}")
    energies = np.vectorize(one, otypes=[float])(distances)
    return float(energies) if energies.ndim == 0 else energies


def smeared_pair_limit(form, smearing_length, bjerrum_length=1.0):
    """u(0) of two unit charges, in kT: l_B/lambda ("slater"), 5 l_B/(8 lambda) ("slater-overlap"),
    l_B/(sigma sqrt(pi)) ("gaussian")."""
    where = "smeared_pair_limit"
    length = _positive(smearing_length, "smearing_length", where)
    return _positive(bjerrum_length, "bjerrum_length", where) * _form(form, where).limit / length


def correction_cutoff(form, smearing_length, bjerrum_length, tolerance=1e-5, largest_charge=1.0):
    """The shortest distance (units of r_c) beyond which the smearing correction u_smeared - u_point
    of two charges `largest_charge` is below `tolerance` kT in energy and kT/r_c in force."""
    where = "correction_cutoff"
    shape = _form(form, where)
    length = _positive(smearing_length, "smearing_length", where)
    scale = _positive(bjerrum_length, "bjerrum_length", where) * _number(largest_charge, "largest_charge", where)**2
    tolerance = _fraction(tolerance, "tolerance", where)

    def tail(x):
        energy = shape.deficit(x, length) / x
        return scale * max(energy, abs(shape.slope(x, length) / x - energy / x))

    low, high = 0.0, length
    while tail(high) > tolerance:
        low, high = high, 2 * high
    for _ in range(60):  # both tails fall monotonically: bisection to double precision
        middle = 0.5 * (low + high)
        low, high = (middle, high) if tail(middle) > tolerance else (low, middle)
    return high


@dataclass
class SmearedElectrostatics:
    """What `add_smeared_electrostatics` added to a System.

    `nonbonded` is the point-charge NonbondedForce (PME), `correction` the short-ranged
    CustomNonbondedForce u_smeared - u_point.  `charge_scale` is OpenMM's charge (e) of a bead
    of valence 1; `cutoff` (PME's real space) and `correction_cutoff` are in units of r_c, and
    `tail` is the correction's energy at its cutoff for the largest charges present (kT): the
    most that any pair loses by the cutoff.
    """
    nonbonded: openmm.NonbondedForce
    correction: openmm.CustomNonbondedForce
    form: str
    charge_scale: float
    cutoff: float
    correction_cutoff: float
    tail: float

    @property
    def forces(self):
        return (self.nonbonded, self.correction)

    def set_force_group(self, group, reciprocal_group=None):
        """Puts both forces in `group` (0-31); PME's reciprocal sum in `reciprocal_group` if given."""
        for force in self.forces:
            force.setForceGroup(group)
        if reciprocal_group is not None:
            self.nonbonded.setReciprocalSpaceForceGroup(reciprocal_group)


def add_smeared_electrostatics(system, charges, bjerrum_length, smearing_length, form="slater", *,
                               units=None, exclusions=(), cutoff=None, tolerance=1e-5, ewald_tolerance=5e-4):
    """Gives the beads of a periodic `system` smeared charges; returns a `SmearedElectrostatics`.

    Two beads of valences z_i, z_j at distance r interact with z_i z_j kT u(r), u the pair
    energy of `form` (`smeared_pair_energy`).  Adds a NonbondedForce (PME, point charges) and
    a CustomNonbondedForce (u_smeared - u_point, out to `correction_cutoff`).

    :param charges: the valence of every particle (units of e; 0 for a neutral bead).
    :param bjerrum_length: l_B = e^2/(4 pi eps kT) in units of r_c, kT and r_c those of `units`; > 0.
    :param smearing_length: lambda of "slater" / "slater-overlap", sigma of "gaussian", in
        units of r_c (or a length Quantity); > 0.
    :param form: "slater", "slater-overlap" or "gaussian" (`SMEARING_FORMS`).
    :param units: the model's `DPDUnits` (r_c, kT); the default is r_c = 1 nm, kT = 1 kJ/mol.
    :param exclusions: pairs (i, j) with no electrostatic interaction at all (in both forces).
    :param cutoff: PME's real-space cutoff (units of r_c); by default the correction's cutoff,
        or 2 if that is shorter and the box allows.  At most half the box's smallest width.
    :param tolerance: the largest correction left out beyond its cutoff, kT and kT/r_c for the
        largest charges; in (0, 1).
    :param ewald_tolerance: PME's relative force error (`setEwaldErrorTolerance`); in (0, 1).

    Arguments are checked before the System is changed: a bad one raises ValueError or
    TypeError naming it and its allowed range.
    """
    units = DPDUnits() if units is None else units
    if not isinstance(units, DPDUnits):
        raise TypeError(f"{_WHERE}: units must be a DPDUnits, got {units!r}")
    r_c = units.length(1.0).value_in_unit(unit.nanometer)
    length = _positive(_reduced_length(smearing_length, r_c, "smearing_length"), "smearing_length")
    bjerrum = _positive(_reduced_length(bjerrum_length, r_c, "bjerrum_length"), "bjerrum_length")
    shape_name = _form_name(form)
    valences = _valences(charges, system)
    pairs = _exclusion_pairs(exclusions, len(valences))
    half_box = _half_box(system) / r_c
    largest = max((abs(z) for z in valences), default=0.0) or 1.0
    tolerance = _fraction(tolerance, "tolerance")
    reach = correction_cutoff(shape_name, length, bjerrum, tolerance, largest)
    if reach > half_box:
        raise ValueError(f"{_WHERE}: the {shape_name} correction with smearing_length {length:g} needs a cutoff of "
                         f"{reach:.4g} r_c for tolerance {tolerance:g}, more than half the box's smallest width "
                         f"({half_box:.4g} r_c); use a larger box, a shorter smearing_length or a larger tolerance")
    real_space = _real_space_cutoff(cutoff, reach, half_box)
    ewald_tolerance = _fraction(ewald_tolerance, "ewald_tolerance")
    kT = units.energy(1.0).value_in_unit(unit.kilojoule_per_mole)
    scale = math.sqrt(kT * bjerrum * r_c / ONE_4PI_EPS0)
    scaled = [z * scale for z in valences]
    nonbonded = _point_charge_force(scaled, pairs, real_space * r_c, ewald_tolerance)
    correction = _correction_force(scaled, pairs, SMEARING_FORMS[shape_name], length * r_c, reach * r_c)
    system.addForce(nonbonded)
    system.addForce(correction)
    shape = SMEARING_FORMS[shape_name]
    tail = bjerrum * largest ** 2 * shape.deficit(reach, length) / reach
    return SmearedElectrostatics(nonbonded, correction, shape_name, scale, real_space, reach, tail)


def fast_pme_grid(nonbonded, box_length):
    """Sets OpenMM's own Ewald parameter and grid for a cubic box of edge box_length (nm) (its
    formula for the force's tolerance), the grid rounded up to a size with no prime factor
    above 5: where the CPU platform has no PME plugin, PME runs the reference FFT, several
    times slower on other sizes (41 against 45).  Returns the grid size."""
    tolerance = nonbonded.getEwaldErrorTolerance()
    alpha = math.sqrt(-math.log(2 * tolerance)) / nonbonded.getCutoffDistance()._value
    size = max(6, math.ceil(2 * alpha * box_length / (3 * tolerance ** 0.2)))
    while not _is_5_smooth(size):
        size += 1
    nonbonded.setPMEParameters(alpha, size, size, size)
    return size


def _is_5_smooth(n):
    """Whether n has no prime factor above 5."""
    for p in (2, 3, 5):
        while n % p == 0:
            n //= p
    return n == 1


def _point_charge_force(charges, pairs, cutoff, ewald_tolerance):
    force = openmm.NonbondedForce()
    force.setName("SmearedElectrostaticsPME")
    force.setNonbondedMethod(openmm.NonbondedForce.PME)
    force.setCutoffDistance(cutoff)
    force.setEwaldErrorTolerance(ewald_tolerance)
    force.setUseDispersionCorrection(False)
    for q in charges:
        force.addParticle(q, 1.0, 0.0)  # epsilon 0: charges only
    # An exception of charge product 0 also takes the pair out of PME's reciprocal sum.
    for i, j in pairs:
        force.addException(i, j, 0.0, 1.0, 0.0)
    return force


def _correction_force(charges, pairs, shape, length, cutoff):
    force = openmm.CustomNonbondedForce(f"-{ONE_4PI_EPS0!r}*q1*q2*deficit/r; deficit = {shape.expression}; "
                                        f"L = {length!r}")
    force.setName("SmearedElectrostaticsCorrection")
    force.addPerParticleParameter("q")
    for q in charges:
        force.addParticle([q])
    for i, j in pairs:
        force.addExclusion(i, j)
    charged = [i for i, q in enumerate(charges) if q != 0]
    if 0 < len(charged) < len(charges):  # neutral beads (a solvent) need no pair search
        force.addInteractionGroup(charged, charged)
    force.setNonbondedMethod(openmm.CustomNonbondedForce.CutoffPeriodic)
    force.setCutoffDistance(cutoff)
    force.setUseLongRangeCorrection(False)
    return force


def _form(name, where=_WHERE):
    return SMEARING_FORMS[_form_name(name, where)]


def _form_name(name, where=_WHERE):
    if not isinstance(name, str) or name not in SMEARING_FORMS:
        raise ValueError(f"{where}: form must be one of {', '.join(map(repr, SMEARING_FORMS))}, got {name!r}")
    return name


def _number(value, name, where=_WHERE):
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise TypeError(f"{where}: {name} must be a number, got {value!r}")
    return float(value)


def _positive(value, name, where=_WHERE):
    value = _number(value, name, where)
    if not (math.isfinite(value) and value > 0):
        raise ValueError(f"{where}: {name} must be > 0 and finite (units of r_c), got {value!r}")
    return value


def _fraction(value, name, where=_WHERE):
    value = _number(value, name, where)
    if not 0 < value < 1:
        raise ValueError(f"{where}: {name} must be in (0, 1), got {value!r}")
    return value


def _reduced_length(value, r_c, name):
    """A reduced length: a plain number as it is, a length Quantity divided by r_c."""
    if unit.is_quantity(value):
        if not value.unit.is_compatible(unit.nanometer):
            raise TypeError(f"{_WHERE}: {name} must be a length (a Quantity in nanometer or a number in units "
                            f"of r_c), got {value}")
        return value.value_in_unit(unit.nanometer) / r_c
    return value


def _valences(charges, system):
    try:
        valences = list(charges)
    except TypeError:
        raise TypeError(f"{_WHERE}: charges must be a sequence of numbers, got {charges!r}") from None
    valences = [_number(z, f"charges[{k}]") for k, z in enumerate(valences)]
    if len(valences) != system.getNumParticles():
        raise ValueError(f"{_WHERE}: charges must have one valence per particle ({system.getNumParticles()}), "
                         f"got {len(valences)}")
    bad = [k for k, z in enumerate(valences) if not math.isfinite(z)]
    if bad:
        raise ValueError(f"{_WHERE}: charges[{bad[0]}] must be finite, got {valences[bad[0]]!r}")
    return valences


def _exclusion_pairs(exclusions, count):
    pairs = set()
    for pair in exclusions:
        try:
            i, j = (int(k) for k in pair)
        except (TypeError, ValueError):
            raise TypeError(f"{_WHERE}: exclusions must be pairs of particle indices, got {pair!r}") from None
        if not (0 <= i < count and 0 <= j < count and i != j):
            raise ValueError(f"{_WHERE}: exclusions must pair two different particles in [0, {count}), got {pair!r}")
        pairs.add((min(i, j), max(i, j)))
    return sorted(pairs)


def _half_box(system):
    """Half the smallest width of the System's periodic box (nm); ValueError if not periodic."""
    if system.getNumForces() > 0 and not system.usesPeriodicBoundaryConditions():
        raise ValueError(f"{_WHERE}: system must be periodic (PME), but none of its forces uses periodic "
                         f"boundary conditions")
    a, b, c = system.getDefaultPeriodicBoxVectors()
    widths = (a[0], b[1], c[2])  # OpenMM's reduced triclinic form: the diagonal gives the widths
    return 0.5 * min(w.value_in_unit(unit.nanometer) for w in widths)


def _real_space_cutoff(cutoff, reach, half_box):
    if cutoff is None:
        return max(reach, min(2.0, half_box))
    cutoff = _number(cutoff, "cutoff")
    if not 0 < cutoff <= half_box:
        raise ValueError(f"{_WHERE}: cutoff must be > 0 and at most half the box's smallest width "
                         f"({half_box:.4g} r_c), got {cutoff!r}")
    return cutoff
