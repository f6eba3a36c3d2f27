"""DPDUnits, the reduced units of a DPD model said as OpenMM Quantities, against exact values:
the defaults (r_c = 1 nm, m = 1 amu, kT = 1 kJ/mol) give tau = 1 ps exactly."""
import math

import pytest
from openmm import unit

import openmmdpd
from openmmdpd import DPDUnits

PS, NM, K, KJ = unit.picosecond, unit.nanometer, unit.kelvin, unit.kilojoule_per_mole
R = 0.008314462618  # kJ/mol/K, exact in the SI
NA = 6.02214076e23  # 1/mol, exact in the SI


def test_the_default_units_are_openmms_own():
    """r_c = 1 nm, m = 1 amu, kT = 1 kJ/mol: tau is 1 ps exactly and every number but the
    temperature passes unchanged."""
    u = DPDUnits()
    assert u.time(1.0) == 1.0 * PS and u.time(0.04) == 0.04 * PS
    assert u.temperature() == openmmdpd.KT_TEMPERATURE and u.temperature(1.0).value_in_unit(K) == 1 / R
    assert u.temperature(2.0) == 2 * openmmdpd.KT_TEMPERATURE
    assert u.friction(4.5) == 4.5 / PS
    assert u.length(10.0) == 10.0 * NM and u.mass(1.0) == 1.0 * unit.dalton
    assert u.energy(3.0) == 3.0 * KJ and u.force(25.0) == 25.0 * KJ / NM
    assert u.pressure(23.65) == 23.65 * KJ / NM**3


def test_tau_is_one_ps_by_openmm_units_own_arithmetic():
    tau = 1.0 * NM * unit.sqrt(1.0 * unit.dalton / (1.0 * KJ / unit.AVOGADRO_CONSTANT_NA) / unit.AVOGADRO_CONSTANT_NA)
    assert tau.value_in_unit(PS) == pytest.approx(1.0, rel=1e-14)


def test_a_model_with_its_own_cutoff_mass_and_kT():
    kT, rc, m = 2.5, 0.6465, 36.0  # e.g. three water molecules a bead at about 300 K
    u = DPDUnits(kT=kT * KJ, cutoff=rc * NM, mass=m * unit.dalton)
    tau = rc * math.sqrt(m / kT)
    assert u.time(1.0) == tau * PS and u.time(0.04) == 0.04 * tau * PS
    assert u.temperature(1.0).value_in_unit(K) == pytest.approx(kT / R, rel=1e-15)
    assert u.friction(4.5) == 4.5 / tau / PS
    assert u.length(2.0) == 2.0 * rc * NM and u.mass(2.0) == 2.0 * m * unit.dalton
    assert u.energy(1.0) == kT * KJ
    assert u.force(25.0) == 25.0 * kT / rc * KJ / NM
    assert u.pressure(1.0) == kT / rc**3 * KJ / NM**3
    # The same through openmm.unit: tau = r_c sqrt(m/kT), with m per mole as kT is.
    tau_quantity = u.length(1.0) * unit.sqrt(u.mass(1.0) / u.energy(1.0))
    assert tau_quantity.value_in_unit(PS) == pytest.approx(tau, rel=1e-14)


def test_the_friction_rate_for_beads_of_other_masses():
    """The integrators' pair coefficient is 2 mu_ij times the rate: the rate that gives DPD's
    gamma (units of m/tau) depends on the pair's masses, and is gamma/tau for two beads of mass m."""
    kT, rc, m = 2.5, 0.6465, 36.0
    u = DPDUnits(kT=kT * KJ, cutoff=rc * NM, mass=m * unit.dalton)
    tau = rc * math.sqrt(m / kT)
    for mass1, mass2 in [(1.0, 1.0), (1.0, 3.0), (2.0, 2.0), (0.5, 4.0)]:
        rate = u.friction(4.5, mass1, mass2).value_in_unit(PS**-1)
        mu = (mass1 * m) * (mass2 * m) / ((mass1 + mass2) * m)  # amu
        assert 2 * mu * rate == pytest.approx(4.5 * m / tau, rel=1e-14)  # gamma in amu/ps
    assert u.friction(4.5) == u.friction(4.5, 1.0, 1.0) == 4.5 / tau / PS
    assert DPDUnits().friction(4.5, mass1=1.0, mass2=2.0).value_in_unit(PS**-1) == pytest.approx(3.375, rel=1e-15)
    with pytest.raises(ValueError, match=r"DPDUnits.friction: mass1 and mass2 must be > 0 \(reduced masses\), "
                                         r"got 0.0, 1.0"):
        u.friction(4.5, 0.0)


def test_the_pressure_in_bar_for_a_barostat():
    p = DPDUnits().pressure(1.0) / unit.AVOGADRO_CONSTANT_NA
    assert p.value_in_unit(unit.bar) == pytest.approx(1e25 / NA, rel=1e-14)  # 16.6054 bar


def test_kT_as_a_temperature_or_a_plain_number():
    assert DPDUnits(kT=300 * K).energy(1.0).value_in_unit(KJ) == pytest.approx(300 * R, rel=1e-15)
    assert DPDUnits(kT=300 * K).temperature(1.0).value_in_unit(K) == pytest.approx(300, rel=1e-15)
    assert DPDUnits(kT=2.0).energy(1.0) == DPDUnits(kT=2000 * unit.joule / unit.mole).energy(1.0)
    assert repr(DPDUnits(kT=2.0, cutoff=0.5, mass=3)) == "DPDUnits(kT=2.0, cutoff=0.5, mass=3.0)"


@pytest.mark.parametrize("arguments, message", [
    ({"kT": 0.0}, "DPDUnits: kT must be > 0 and finite (kJ/mol), got 0.0"),
    ({"kT": -1.0}, "DPDUnits: kT must be > 0"),
    ({"cutoff": float("nan")}, "DPDUnits: cutoff must be > 0 and finite (nm), got nan"),
    ({"mass": 0}, "DPDUnits: mass must be > 0 and finite (amu), got 0.0"),
])
def test_units_out_of_range_are_refused(arguments, message):
    with pytest.raises(ValueError, match=message.replace("(", r"\(").replace(")", r"\)")):
        DPDUnits(**arguments)


def test_wrong_types_are_refused():
    with pytest.raises(TypeError, match="DPDUnits: cutoff must be a length"):
        DPDUnits(cutoff=1 * PS)
    with pytest.raises(TypeError, match="DPDUnits.time: t must be a number, got 0.04 ps"):
        DPDUnits().time(0.04 * PS)  # a reduced number is a plain number


@pytest.mark.parametrize("method, value, message", [
    ("time", -0.01, "DPDUnits.time: t must be finite and >= 0 (a reduced number), got -0.01"),
    ("friction", -4.5, "DPDUnits.friction: gamma must be finite and >= 0"),
    ("temperature", -1.0, "DPDUnits.temperature: kT must be finite and >= 0"),
    ("mass", -1.0, "DPDUnits.mass: x must be finite and >= 0"),
    ("force", float("inf"), "DPDUnits.force: a must be a finite number (a reduced number), got inf"),
])
def test_reduced_numbers_out_of_range_are_refused(method, value, message):
    with pytest.raises(ValueError, match=message.replace("(", r"\(").replace(")", r"\)")):
        getattr(DPDUnits(), method)(value)


def test_signed_quantities_may_be_negative():
    assert DPDUnits().force(-5.0) == -5.0 * KJ / NM and DPDUnits().length(-0.5) == -0.5 * NM
