"""DPD reduced units inside OpenMM.

Taking rc = 1 nm, m = 1 amu and kT = 1 kJ/mol makes the reduced time unit
rc*sqrt(m/kT) exactly 1 ps, so reduced numbers can be passed to OpenMM unchanged;
only the temperature needs converting (kT = 1 is T = 120.27236 K).
"""
import numbers

from openmm import unit

__all__ = ["MOLAR_GAS_CONSTANT", "KT_TEMPERATURE", "reduced_temperature",
           "kT_from_temperature", "strip_units"]

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
