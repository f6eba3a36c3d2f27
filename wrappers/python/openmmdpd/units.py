"""DPD reduced units inside OpenMM.

Taking rc = 1 nm, m = 1 amu and kT = 1 kJ/mol makes the reduced time unit
rc*sqrt(m/kT) exactly 1 ps, so reduced numbers can be passed to OpenMM unchanged;
only the temperature needs converting (kT = 1 is T = 120.27236 K).
"""
from openmm import unit

__all__ = ["MOLAR_GAS_CONSTANT", "KT_TEMPERATURE", "reduced_temperature",
           "kT_from_temperature", "strip_units"]

#: R in kJ/mol/K, the value the design fixes (2019 SI).
MOLAR_GAS_CONSTANT = 0.008314462618

#: The temperature whose kT is 1 kJ/mol, i.e. reduced kT = 1.
KT_TEMPERATURE = (1.0 / MOLAR_GAS_CONSTANT) * unit.kelvin


def reduced_temperature(kT=1.0):
    """Temperature (Quantity, kelvin) for a reduced kT in kJ/mol."""
    return kT * KT_TEMPERATURE


def kT_from_temperature(temperature):
    """Reduced kT (float, kJ/mol) for a temperature: a Quantity, or a float in kelvin."""
    return strip_units(temperature, unit.kelvin) * MOLAR_GAS_CONSTANT


def strip_units(value, target_unit):
    """The float value of `value` in `target_unit`; plain numbers are taken as already in it."""
    if unit.is_quantity(value):
        if not value.unit.is_compatible(target_unit):
            raise TypeError(f"expected a quantity in units compatible with {target_unit}, "
                            f"got {value}")
        return value.value_in_unit(target_unit)
    return float(value)
