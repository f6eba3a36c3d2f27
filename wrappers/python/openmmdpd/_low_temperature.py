"""A warning when an integrator is given a temperature that is almost surely a reduced kT.

OpenMM takes temperatures in kelvin, and DPD models are written with kT = 1, so
`ShardlowIntegrator(1.0, 4.5, 1.0, 0.04)` runs at 1 K, kT = 0.0083 kJ/mol, without a word.
Importing openmmdpd wraps each integrator class's constructor and setTemperature to warn when
the temperature is above 0 K (0 K is a deliberate noiseless run) and below 10 K.

Each line of code outside the package that sets such a temperature warns once, whatever the
value and the warning filter, so that a loop making many integrators warns once; the line is
the caller's, not the package's, so that the message points at the code to fix.
"""
import functools
import sys
import warnings

from openmm import unit

from .units import KT_TEMPERATURE, MOLAR_GAS_CONSTANT

#: Temperatures above 0 K and below this (K) warn.
LOW_TEMPERATURE = 10.0

# (file, line) of each caller warned already.
_warned_at = set()


class LowTemperatureWarning(UserWarning):
    """An integrator was given a temperature above 0 K and below 10 K, almost surely a
    reduced kT (such as 1.0) read as kelvin.

    OpenMM takes kelvin: kT = 1 kJ/mol is ``openmmdpd.KT_TEMPERATURE`` (120.27 K), or
    ``openmmdpd.reduced_temperature(kT)``, or ``openmmdpd.DPDUnits(...).temperature(1.0)``.
    Each line of code warns once.  To run that cold on purpose, silence it with
    ``warnings.filterwarnings("ignore", category=openmmdpd.LowTemperatureWarning)``.
    """


def _outside_package():
    """(the stacklevel at which warnings.warn, called by this function's caller, names the
    first frame outside the package; that frame), or (level, None) if there is none."""
    frame, level = sys._getframe(1), 1
    while frame is not None and (frame.f_globals.get("__name__") or "").partition(".")[0] == __package__:
        frame, level = frame.f_back, level + 1
    return level, frame


def _check(integrator, where):
    kelvin = integrator.getTemperature().value_in_unit(unit.kelvin)
    if not 0 < kelvin < LOW_TEMPERATURE:
        return
    level, frame = _outside_package()
    site = None if frame is None else (frame.f_code.co_filename, frame.f_lineno)
    if site in _warned_at:
        return
    _warned_at.add(site)
    warnings.warn(f"{where}: temperature {kelvin:g} K is kT = {kelvin * MOLAR_GAS_CONSTANT:.4g} kJ/mol, almost "
                  f"surely a reduced kT read as kelvin (OpenMM takes kelvin). For kT = 1 kJ/mol pass "
                  f"openmmdpd.reduced_temperature(1.0) (= openmmdpd.KT_TEMPERATURE, "
                  f"{KT_TEMPERATURE.value_in_unit(unit.kelvin):.5f} K) or openmmdpd.DPDUnits().temperature(1.0). "
                  f"If {kelvin:g} K is meant, silence this with warnings.filterwarnings(\"ignore\", "
                  f"category=openmmdpd.LowTemperatureWarning). (Warned once per line of code.)",
                  LowTemperatureWarning, stacklevel=level)


def _warning_after(method, where):
    if getattr(method, "_openmmdpd_low_temperature", False):
        return method  # already wrapped (the package imported again, e.g. reloaded)

    @functools.wraps(method)
    def wrapper(self, *args, **kwargs):
        result = method(self, *args, **kwargs)
        _check(self, where(self))
        return result

    wrapper._openmmdpd_low_temperature = True
    return wrapper


def install(base, integrators):
    """Wrap `base`'s setTemperature and each of `integrators`' constructors (and any
    setTemperature of their own)."""
    for cls in (base,) + tuple(integrators):
        if "setTemperature" in vars(cls):
            cls.setTemperature = _warning_after(cls.setTemperature,
                                                lambda self: f"{type(self).__name__}.setTemperature")
    for cls in integrators:
        cls.__init__ = _warning_after(cls.__init__, lambda self: type(self).__name__)
