"""chi -> a_ij (Groot and Warren 1997): the fitted slopes at the two densities they were fitted
at, the inverse, and a refusal of any other density rather than an extrapolation."""
import pytest
from openmm import unit

import openmmdpd
from openmmdpd import DPDUnits, a_from_chi, chi_from_a

NM, KJ = unit.nanometer, unit.kilojoule_per_mole


def test_a_from_chi_at_the_two_fitted_densities():
    assert a_from_chi(0.0) == 25.0 and a_from_chi(0.0, density=5) == 15.0  # a_ii = 75/rho
    assert a_from_chi(1.0) == 25.0 + 1 / 0.286  # 28.50: Delta a = 3.50 chi at rho = 3
    assert a_from_chi(1.0, density=5.0) == 15.0 + 1 / 0.689
    assert a_from_chi(2.0, a_ii=30.0) == 30.0 + 2 / 0.286
    assert round(a_from_chi(1.0), 2) == 28.50


@pytest.mark.parametrize("density", [3.0, 5.0])
@pytest.mark.parametrize("chi", [0.0, 0.3, 1.0, 6.0])
def test_chi_from_a_inverts_it(chi, density):
    assert chi_from_a(a_from_chi(chi, density), density) == pytest.approx(chi, abs=1e-12)


def test_other_densities_are_refused_not_extrapolated():
    for density in (1.0, 4.0, 3.1, 10.0):
        with pytest.raises(ValueError, match=r"a_from_chi: density must be 3 or 5 .*Groot and Warren \(1997\)"):
            a_from_chi(1.0, density=density)
        with pytest.raises(ValueError, match=r"chi_from_a: density must be 3 or 5 .*got " + str(density)):
            chi_from_a(30.0, density=density)


def test_bad_chi_and_a_are_refused():
    with pytest.raises(ValueError, match=r"a_from_chi: chi must be finite and >= 0 .*got -0.5"):
        a_from_chi(-0.5)
    with pytest.raises(ValueError, match=r"chi_from_a: a_ij must be finite and >= a_ii = 25 .*got 20"):
        chi_from_a(20)
    with pytest.raises(ValueError, match=r"a_from_chi: a_ii must be finite and > 0"):
        a_from_chi(1.0, a_ii=0.0)
    with pytest.raises(TypeError, match="a_from_chi: chi must be a number"):
        a_from_chi("1")


def test_a_from_chi_into_the_force_in_openmm_units():
    u = DPDUnits(kT=2.0, cutoff=0.5)
    force = openmmdpd.DPDSoftRepulsionForce(u.force(25.0), u.length(1.0))
    force.addTypePair(0, 1, u.force(a_from_chi(1.0)), u.length(1.0))
    assert force.getDefaultA() == (25.0 * 2.0 / 0.5) * KJ / NM
    assert force.getTypePairParameters(0)[2].value_in_unit(KJ / NM) == pytest.approx((25 + 1 / 0.286) * 4.0)
