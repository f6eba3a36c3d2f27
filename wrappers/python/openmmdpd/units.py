"""DPD reduced units inside OpenMM.

Taking rc = 1 nm, m = 1 amu and kT = 1 kJ/mol makes the reduced time unit
rc*sqrt(m/kT) exactly 1 ps, so reduced numbers can be passed to OpenMM unchanged;
only the temperature needs converting (kT = 1 is T = 120.27236 K).  DPDUnits maps the
reduced numbers of a model with another r_c, m or kT.
"""
import math
import numbers

from openmm import unit

__all__ = ["MOLAR_GAS_CONSTANT", "KT_TEMPERATURE", "reduced_temperature",
           "kT_from_temperature", "strip_units", "DPDUnits"]

#: R in kJ/mol/K, the value the design fixes (2019 SI).
MOLAR_GAS_CONSTANT = 0.008314462618

#: The temperature whose kT is 1 kJ/mol, i.e. reduced kT = 1.
KT_TEMPERATURE = (1.0 / MOLAR_GAS_CONSTANT) * unit.kelvin


def reduced_temperature(kT=1.0):
    """Temperature (Quantity, kelvin) for kT: an energy Quantity (per mole), or a float in kJ/mol."""
    return strip_units(kT, unit.kilojoule_per_mole, "kT", "reduced_temperature") * KT_TEMPERATURE


def kT_from_temperature(temperature):
    """Reduced kT (float, kJ/mol) for a temperature: a Quantity, or a float in kelvin."""
    return strip_units(temperature, unit.kelvin, "temperature", "kT_from_temperature") * MOLAR_GAS_CONSTANT


# How an error message describes an argument in each unit: (what it is, the unit's name).
_KINDS = {
    unit.kelvin: ("a temperature", "kelvin"),
    unit.picosecond**-1: ("a rate", "1/picosecond"),
    unit.nanometer: ("a length", "nanometer"),
    unit.picosecond: ("a time", "picosecond"),
    unit.kilojoule_per_mole / unit.nanometer: ("a force", "kilojoule/mole/nanometer"),
    unit.kilojoule_per_mole: ("an energy", "kilojoule/mole"),
    unit.kilojoule_per_mole / unit.picosecond: ("a power", "kilojoule/mole/picosecond"),
    (unit.kilojoule_per_mole / unit.nanometer)**2: ("a squared force", "(kilojoule/mole/nanometer)**2"),
    (unit.kilojoule_per_mole / unit.nanometer)**2 * unit.picosecond:
        ("a squared force times a time", "(kilojoule/mole/nanometer)**2*picosecond"),
    unit.dalton: ("a mass", "dalton"),
}


def strip_units(value, target_unit, name="value", where="strip_units"):
    """The float value of `value` in `target_unit`; plain numbers are taken as already in it.

    `target_unit` None means a plain number.  Anything else (a Quantity in other units, a
    string, None, ...) raises TypeError "where: name must be ..., got value", so that a
    wrapper can say which class, method and parameter the bad argument was given to.
    """
    if unit.is_quantity(value):
        if target_unit is not None and value.unit.is_compatible(target_unit):
            return float(value.value_in_unit(target_unit))
    elif isinstance(value, numbers.Real) and not isinstance(value, bool):
        return float(value)
    if target_unit is None:
        expected = "a number"
    else:
        what, unit_name = _KINDS.get(target_unit, ("a quantity", str(target_unit)))
        expected = f"{what} (a Quantity in {unit_name} or a number)"
    got = str(value) if unit.is_quantity(value) else repr(value)
    raise TypeError(f"{where}: {name} must be {expected}, got {got}")


class DPDUnits:
    """A DPD model's reduced units, as the OpenMM Quantities its numbers stand for.

    DPD states a model in units of the cutoff r_c (length), the bead mass m and the thermal
    energy kT, whose time unit is tau = r_c sqrt(m/kT).  Each method takes a reduced number
    (a plain float) and gives the Quantity in OpenMM's units to pass to OpenMM and openmmdpd.
    The defaults, r_c = 1 nm, m = 1 amu and kT = 1 kJ/mol, make tau exactly 1 ps (1 kJ/mol
    is 1 amu nm^2/ps^2), so every reduced number but the temperature is then its own value in
    OpenMM's units.

    :param kT: the energy unit: an energy Quantity (per mole), a temperature Quantity (then
        kT = R T), or a number in kJ/mol; > 0.
    :param cutoff: the length unit r_c: a length Quantity or a number in nm; > 0.
    :param mass: the mass unit m, a bead's mass: a mass Quantity or a number in amu
        (dalton); > 0.

    ``DPDUnits().temperature(1.0)`` is ``KT_TEMPERATURE`` (120.27 K) and
    ``DPDUnits().time(0.04)`` is 0.04 ps.  Arguments that are not finite plain numbers, or
    outside a method's range, raise TypeError or ValueError naming the method and the value.
    """

    def __init__(self, kT=1.0, cutoff=1.0, mass=1.0):
        if unit.is_quantity(kT) and kT.unit.is_compatible(unit.kelvin):
            kT = kT_from_temperature(kT)
        self._kT = _positive(strip_units(kT, unit.kilojoule_per_mole, "kT", "DPDUnits"), "kT", "kJ/mol")
        self._cutoff = _positive(strip_units(cutoff, unit.nanometer, "cutoff", "DPDUnits"), "cutoff", "nm")
        self._mass = _positive(strip_units(mass, unit.dalton, "mass", "DPDUnits"), "mass", "amu")
        self._tau = self._cutoff * math.sqrt(self._mass / self._kT)

    def __repr__(self):
        return f"DPDUnits(kT={self._kT!r}, cutoff={self._cutoff!r}, mass={self._mass!r})"

    def temperature(self, kT=1.0):
        """The temperature (Quantity, K) of a reduced kT (in units of the model's kT; >= 0):
        what an integrator's ``temperature`` argument takes."""
        return reduced_temperature(_reduced(kT, "temperature", "kT", 0.0) * self._kT)

    def time(self, t):
        """A time (Quantity, ps) for a reduced time ``t`` (in units of tau; >= 0), e.g. a step
        size ``dt``."""
        return _reduced(t, "time", "t", 0.0) * self._tau * unit.picosecond

    def friction(self, gamma, mass1=1.0, mass2=1.0):
        """The integrators' friction rate (Quantity, 1/ps) that gives DPD's friction coefficient
        ``gamma`` (in units of m/tau; >= 0) between beads of masses ``mass1`` and ``mass2`` (in
        units of m; > 0, 1 by default): gamma / (2 mu_ij) / tau, mu_ij = mass1 mass2 / (mass1 + mass2).

        The integrators take a rate f per type pair and make a particle pair's coefficient
        gamma_ij = 2 mu_ij f, mu_ij being the pair's reduced mass. For two beads of mass m
        (2 mu_ij = m) that is gamma m/tau with f = gamma/tau, the default. For beads of other
        masses the same rate gives another coefficient (2 mu_ij/m times gamma), so give the
        pair's masses to get ``gamma`` for that pair; a type pair whose beads differ in mass
        needs its own rate.

        A Lowe-Andersen collision rate Gamma (in units of 1/tau) does not scale with mass:
        ``friction(Gamma)`` with the default masses gives it.
        """
        gamma = _reduced(gamma, "friction", "gamma", 0.0)
        mass1, mass2 = (_reduced(mass, "friction", name) for mass, name in ((mass1, "mass1"), (mass2, "mass2")))
        if not (mass1 > 0 and mass2 > 0):
            raise ValueError(f"DPDUnits.friction: mass1 and mass2 must be > 0 (reduced masses), got {mass1!r}, "
                             f"{mass2!r}")
        return gamma / (2 * mass1 * mass2 / (mass1 + mass2)) / self._tau / unit.picosecond

    def length(self, x):
        """A length (Quantity, nm) for a reduced length ``x`` (in units of r_c)."""
        return _reduced(x, "length", "x") * self._cutoff * unit.nanometer

    def mass(self, x):
        """A mass (Quantity, amu) for a reduced mass ``x`` (in units of m; >= 0)."""
        return _reduced(x, "mass", "x", 0.0) * self._mass * unit.dalton

    def energy(self, x):
        """An energy (Quantity, kJ/mol) for a reduced energy ``x`` (in units of kT)."""
        return _reduced(x, "energy", "x") * self._kT * unit.kilojoule_per_mole

    def force(self, a):
        """A force (Quantity, kJ/mol/nm) for a reduced force ``a`` (in units of kT/r_c), such
        as the repulsion parameter a_ij that DPDSoftRepulsionForce takes."""
        return _reduced(a, "force", "a") * self._kT / self._cutoff * unit.kilojoule_per_mole / unit.nanometer

    def pressure(self, p):
        """A pressure (Quantity, kJ/mol/nm^3, the unit of the integrators' pressure tensor) for
        a reduced pressure ``p`` (in units of kT/r_c^3).

        A barostat takes bar: ``(units.pressure(p) / unit.AVOGADRO_CONSTANT_NA).in_units_of(unit.bar)``
        (1 kJ/mol/nm^3 is 16.6054 bar).
        """
        return _reduced(p, "pressure", "p") * self._kT / self._cutoff**3 * unit.kilojoule_per_mole / unit.nanometer**3


def _positive(value, name, unit_name):
    if not (math.isfinite(value) and value > 0):
        raise ValueError(f"DPDUnits: {name} must be > 0 and finite ({unit_name}), got {value!r}")
    return value


def _reduced(value, method, name, minimum=None):
    """`value`, a reduced number, as a float: finite and, if `minimum` is given, >= it."""
    value = strip_units(value, None, name, f"DPDUnits.{method}")
    if not math.isfinite(value) or (minimum is not None and value < minimum):
        allowed = "a finite number" if minimum is None else f"finite and >= {minimum:g}"
        raise ValueError(f"DPDUnits.{method}: {name} must be {allowed} (a reduced number), got {value!r}")
    return value
