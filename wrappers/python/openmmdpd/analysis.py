"""Observables of the DPD papers (algorithms.md §9) as plain numpy, in reduced units.

Arguments may be OpenMM Quantities (converted to nm, nm/ps, amu) or plain arrays
already in those units.
"""
import numpy as np
from openmm import unit
from pymbar import timeseries

__all__ = ["kinetic_temperature", "block_average", "standard_error", "ratio_with_error", "radial_distribution",
           "radius_of_gyration", "velocity_autocorrelation"]


def _array(value, target_unit):
    if unit.is_quantity(value):
        value = value.value_in_unit(target_unit)
    elif isinstance(value, (list, tuple)) and value and unit.is_quantity(value[0]):
        value = [v.value_in_unit(target_unit) for v in value]  # e.g. System.getParticleMass()
    return np.asarray(value, dtype=float)


def kinetic_temperature(velocities, masses):
    """Reduced <kT> = sum m v^2 / (3N - 3): m v^2 is already kJ/mol, and kT = 1 kJ/mol.

    3 degrees of freedom are removed because DPD conserves total momentum.
    """
    v = _array(velocities, unit.nanometer / unit.picosecond).reshape(-1, 3)
    m = _array(masses, unit.dalton).reshape(-1)
    return float(np.sum(m[:, None] * v * v) / (3 * len(v) - 3))


def block_average(samples, nblocks=10):
    """(mean, standard error) of correlated samples from the scatter of nblocks block means.

    Trailing samples that do not fill a whole block are dropped.
    """
    samples = np.asarray(samples, dtype=float)
    block_size = len(samples) // nblocks
    if nblocks < 2 or block_size < 1:
        raise ValueError(f"need at least 2 blocks of 1 sample; got {len(samples)} samples "
                         f"for {nblocks} blocks")
    means = samples[:nblocks * block_size].reshape(nblocks, block_size).mean(axis=1)
    return float(means.mean()), float(means.std(ddof=1) / np.sqrt(nblocks))


def standard_error(samples):
    """Standard error of the mean of a correlated time series: sqrt(g var / n), with g the
    statistical inefficiency (pymbar's timeseries), so every sample counts as 1/g of one.

    nan for fewer than 2 samples; 0 for a constant series (pymbar refuses zero variance).
    """
    x = np.asarray(samples, dtype=float)
    if len(x) < 2:
        return float("nan")
    if np.ptp(x) == 0:
        return 0.0
    return float(np.sqrt(timeseries.statisticalInefficiency(x) * x.var() / len(x)))


def ratio_with_error(numerator, denominator):
    """(<a> / <b>, its standard error) for paired series a, b, such as the configurational
    temperature <sum |F|^2> / <sum lap U>: linearised, the error of the ratio R is that of
    the mean of a - R b, divided by <b>."""
    a, b = np.asarray(numerator, dtype=float), np.asarray(denominator, dtype=float)
    ratio = a.mean() / b.mean()
    return float(ratio), standard_error(a - ratio * b) / abs(b.mean())


def radial_distribution(positions, box_length, r_max, nbins, chunk=256):
    """g(r) of one configuration in a cubic periodic box; returns (r_centres, g).

    Brute force over pairs i < j with the minimum image, `chunk` rows at a time so memory
    stays at chunk x N x 3 doubles. Normalised by the N(N-1)/2 pairs a uniform fluid puts
    in each shell, so ideal gas gives g = 1 exactly on average. r_max must be <= L/2.
    """
    x = _array(positions, unit.nanometer).reshape(-1, 3)
    length = float(_array(box_length, unit.nanometer))
    if r_max > length / 2:
        raise ValueError(f"r_max = {r_max} exceeds half the box ({length / 2})")
    n = len(x)
    edges = np.linspace(0.0, r_max, nbins + 1)
    counts = np.zeros(nbins)
    for start in range(0, n, chunk):
        stop = min(start + chunk, n)
        d = x[start:stop, None, :] - x[None, start:, :]
        d -= length * np.round(d / length)
        r = np.sqrt(np.einsum("ijk,ijk->ij", d, d))
        # Keep j > i only: column c of this block is particle start + c.
        upper = np.arange(n - start)[None, :] > np.arange(stop - start)[:, None]
        counts += np.histogram(r[upper], bins=edges)[0]
    shell_volumes = 4.0 / 3.0 * np.pi * (edges[1:] ** 3 - edges[:-1] ** 3)
    expected = 0.5 * n * (n - 1) / length ** 3 * shell_volumes
    return 0.5 * (edges[1:] + edges[:-1]), counts / expected


def radius_of_gyration(positions_of_chain):
    """Rg = sqrt(mean |r_i - r_cm|^2) of one chain (equal masses; positions unwrapped)."""
    x = _array(positions_of_chain, unit.nanometer).reshape(-1, 3)
    return float(np.sqrt(np.mean(np.sum((x - x.mean(axis=0)) ** 2, axis=1))))


def velocity_autocorrelation(velocities, max_lag):
    """Normalised C(k) = <v(t) . v(t + k)> / <v . v> for lags k = 0 .. max_lag (in frames).

    velocities: frames x particles x 3, equally spaced in time; averaged over particles
    and over every time origin with a full lag (FFT along time, zero-padded).
    """
    v = _array(velocities, unit.nanometer / unit.picosecond)
    frames = v.shape[0]
    if v.ndim != 3 or v.shape[2] != 3 or not 0 < max_lag < frames:
        raise ValueError(f"need frames x particles x 3 velocities and 0 < max_lag < frames; "
                         f"got shape {v.shape} and max_lag {max_lag}")
    size = 1 << int(np.ceil(np.log2(2 * frames)))
    spectrum = np.fft.rfft(v.reshape(frames, -1), n=size, axis=0)
    correlation = np.fft.irfft(np.abs(spectrum) ** 2, n=size, axis=0)[:max_lag + 1].sum(axis=1)
    correlation /= frames - np.arange(max_lag + 1)  # origins per lag
    return correlation / correlation[0]
