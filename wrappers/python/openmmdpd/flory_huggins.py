"""Repulsion parameters from Flory-Huggins chi (Groot and Warren 1997).

Groot and Warren mapped the soft repulsion onto Flory-Huggins theory by simulating binary
mixtures of beads with a_AA = a_BB and a_AB = a_AA + Delta a.  They found chi linear in
Delta a, with slopes fitted at two densities (in beads per r_c^3, kT = 1):

    chi = (0.286 +- 0.002) Delta a   at rho = 3,
    chi = (0.689 +- 0.002) Delta a   at rho = 5.

The slope depends on the density in a way the paper does not give between or beyond these
two, so other densities are refused rather than interpolated.
Both fits have like beads at a_ii = 75/rho; an a_ii given otherwise is used with the same
slope, an extrapolation the paper does not test.
"""
import math

from .units import strip_units

__all__ = ["a_from_chi", "chi_from_a"]

# chi / Delta a at each density (beads per r_c^3) Groot and Warren (1997) fitted it for.
_SLOPES = {3.0: 0.286, 5.0: 0.689}


def a_from_chi(chi, density=3.0, a_ii=None):
    """The repulsion a_ij between unlike beads for a Flory-Huggins ``chi`` (Groot and Warren 1997).

    a_ij = a_ii + chi / s(density), with s = 0.286 at density 3 and 0.689 at density 5, the
    slopes of chi = s (a_ij - a_ii) that R. D. Groot and P. B. Warren, J. Chem. Phys. 107,
    4423 (1997), fitted to simulations of binary mixtures.  At density 3 this is
    a_ij = a_ii + 3.50 chi: 25 + 3.50 chi for water-like beads.  (The rule
    a_ij = a_ii + 3.27 chi, often quoted for density 3, is a slope of 0.306, with a Delta a
    6.5 % smaller.)

    Everything is reduced (a in kT/r_c, density in beads per r_c^3); ``DPDUnits.force`` gives
    the Quantity in kJ/mol/nm.

    :param chi: the Flory-Huggins parameter, finite and >= 0 (the fits are of demixing,
        a_ij >= a_ii).
    :param density: the number density, 3 or 5: the only ones the paper fitted the slope at;
        any other raises ValueError.
    :param a_ii: the repulsion between like beads, > 0; by default 75/density (25 at density 3,
        15 at density 5), the choice Groot and Warren made to match water's compressibility.
        The slopes were fitted with a_ii = 75/density; another a_ii reuses them unchanged, which
        the paper does not check (chi per Delta a may differ for a stiffer or softer fluid).
    :returns: a_ij (float, kT/r_c).
    """
    slope, a_ii = _slope_and_a_ii(density, a_ii, "a_from_chi")
    chi = strip_units(chi, None, "chi", "a_from_chi")
    if not (math.isfinite(chi) and chi >= 0):
        raise ValueError(f"a_from_chi: chi must be finite and >= 0 (the fits are of demixing), got {chi!r}")
    return a_ii + chi / slope


def chi_from_a(a_ij, density=3.0, a_ii=None):
    """The Flory-Huggins chi of a repulsion ``a_ij`` between unlike beads (Groot and Warren 1997).

    The inverse of :func:`a_from_chi`: chi = s(density) (a_ij - a_ii), with the same slopes
    s (0.286 at density 3, 0.689 at density 5) and the same reduced units.

    :param a_ij: the repulsion between unlike beads (kT/r_c), finite and >= a_ii.
    :param density: the number density, 3 or 5; any other raises ValueError.
    :param a_ii: the repulsion between like beads, > 0; by default 75/density. Another a_ii
        reuses the slope fitted with a_ii = 75/density, as in :func:`a_from_chi`.
    :returns: chi (float).
    """
    slope, a_ii = _slope_and_a_ii(density, a_ii, "chi_from_a")
    a_ij = strip_units(a_ij, None, "a_ij", "chi_from_a")
    if not (math.isfinite(a_ij) and a_ij >= a_ii):
        raise ValueError(f"chi_from_a: a_ij must be finite and >= a_ii = {a_ii:g} (the fits are of demixing), "
                         f"got {a_ij!r}")
    return slope * (a_ij - a_ii)


def _slope_and_a_ii(density, a_ii, where):
    density = strip_units(density, None, "density", where)
    slope = next((s for rho, s in _SLOPES.items() if math.isclose(density, rho, rel_tol=1e-9)), None)
    if slope is None:
        raise ValueError(f"{where}: density must be 3 or 5 (beads per r_c^3), the densities Groot and Warren (1997) "
                         f"fitted chi against Delta a at, got {density!r}; at another density, fit chi to "
                         f"simulations of the model")
    if a_ii is None:
        return slope, 75.0 / density
    a_ii = strip_units(a_ii, None, "a_ii", where)
    if not (math.isfinite(a_ii) and a_ii > 0):
        raise ValueError(f"{where}: a_ii must be finite and > 0 (kT/r_c), got {a_ii!r}")
    return slope, a_ii
