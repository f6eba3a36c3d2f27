"""Observables of the DPD papers (docs/theory/observables.md) in reduced units: plain numpy, and MDAnalysis
for g(r) and the mean squared displacement.

Arguments may be OpenMM Quantities (converted to nm, nm/ps, amu) or plain arrays
already in those units.
"""
import warnings

import numpy as np
from openmm import unit
from pymbar import timeseries

__all__ = ["kinetic_temperature", "block_average", "standard_error", "ratio_with_error", "median_with_error",
           "radial_distribution",
           "frame_radial_distributions", "mean_squared_displacement", "grouped_squared_displacement", "radius_of_gyration",
           "velocity_autocorrelation"]


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


def jackknife_error(left_out):
    """The jackknife standard error of an estimate from its values with each of n segments left
    out in turn: sqrt((n - 1)/n sum (x_i - mean)^2)."""
    x = np.asarray(left_out, dtype=float)
    return float(np.sqrt((len(x) - 1) / len(x) * np.sum((x - x.mean()) ** 2)))


def ratio_with_error(numerator, denominator):
    """(<a> / <b>, its standard error) for paired series a, b, such as the configurational
    temperature <sum |F|^2> / <sum lap U>: linearised, the error of the ratio R is that of
    the mean of a - R b, divided by <b>."""
    a, b = np.asarray(numerator, dtype=float), np.asarray(denominator, dtype=float)
    ratio = a.mean() / b.mean()
    return float(ratio), standard_error(a - ratio * b) / abs(b.mean())


def _mdanalysis():
    """MDAnalysis, imported on first use (it takes a second) without the DeprecationWarning of
    MDAnalysis 2.4's import of xdrlib (imported first here: MDAnalysis resets the filters)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        try:
            import xdrlib  # noqa: F401
        except ImportError:  # Python 3.13 has none; nor does MDAnalysis need it there
            pass
        import MDAnalysis
        import MDAnalysis.analysis.msd
        import MDAnalysis.analysis.rdf
        import MDAnalysis.coordinates.memory
    return MDAnalysis


def _universe(frames, box_length, frame_time=1.0):
    """An in-memory MDAnalysis Universe of frames x particles x 3 positions (nm) in a cubic box."""
    mda = _mdanalysis()
    frames = np.asarray(frames, dtype=np.float32)
    universe = mda.Universe.empty(frames.shape[1], trajectory=True)
    universe.load_new(frames, format=mda.coordinates.memory.MemoryReader, dt=frame_time,
                      dimensions=np.array([box_length] * 3 + [90.0] * 3, dtype=np.float32))
    return universe


def frame_radial_distributions(frames, box_length, r_max, nbins):
    """(r_centres, g): g(r) of each frame (one row per frame) of frames x particles x 3
    positions in a cubic periodic box, by MDAnalysis's InterRDF (every ordered pair but a
    particle with itself, so an ideal gas gives g = 1 on average). r_max must be <= L/2."""
    frames = np.asarray(frames, dtype=float)
    length = float(box_length)
    if r_max > length / 2:
        raise ValueError(f"r_max = {r_max} exceeds half the box ({length / 2})")
    everyone = _universe(np.mod(frames, length), length).atoms  # wrapped: float32 keeps 1e-7 L
    g = [_mdanalysis().analysis.rdf.InterRDF(everyone, everyone, nbins=nbins, range=(0.0, r_max), exclusion_block=(1, 1)).run(k, k + 1)
         for k in range(len(frames))]
    return g[0].results.bins, np.array([rdf.results.rdf for rdf in g])


def median_with_error(values):
    """(median, its standard error) of independent values, the error from their median absolute
    deviation (1.4826 MAD estimates a normal spread's sigma, and the median of n values has a
    standard error of 1.2533 sigma / sqrt(n)), so that one outlier does not set it.  Asymptotic:
    for 7 values it reads about 9 % low."""
    x = np.asarray(values, dtype=float)
    median = float(np.median(x))
    return median, 1.2533 * 1.4826 * float(np.median(np.abs(x - median))) / np.sqrt(len(x))


def radial_distribution(positions, box_length, r_max, nbins):
    """g(r) of one configuration in a cubic periodic box; returns (r_centres, g).

    Normalised by the N(N-1)/2 pairs a uniform fluid puts in each shell, so ideal gas gives
    g = 1 exactly on average (see frame_radial_distributions). r_max must be <= L/2.
    """
    x = _array(positions, unit.nanometer).reshape(1, -1, 3)
    r, g = frame_radial_distributions(x, float(_array(box_length, unit.nanometer)), r_max, nbins)
    return r, g[0]


def _einstein_msd(frames, frame_time):
    return _mdanalysis().analysis.msd.EinsteinMSD(_universe(frames, 1.0, frame_time), select="all", msd_type="xyz",
                                                  fft=False).run()


def mean_squared_displacement(frames, frame_time):
    """(lag times, MSD) of unwrapped frames x particles x 3 positions taken every frame_time,
    averaged over particles and every time origin (MDAnalysis's EinsteinMSD, windowed)."""
    msd = _einstein_msd(frames, frame_time)
    return np.asarray(msd.times), np.asarray(msd.results.timeseries)


def grouped_squared_displacement(frames, frame_time, groups):
    """(lag times, MSD, MSD of each group): mean_squared_displacement's two, and the MSD of
    each of `groups` interleaved sets of particles (lags x groups), whose spread gives the
    error of what is fitted to the MSD."""
    msd = _einstein_msd(frames, frame_time)
    by_particle = np.asarray(msd.results.msds_by_particle)
    by_group = np.stack([by_particle[:, g::groups].mean(axis=1) for g in range(groups)], axis=1)
    return np.asarray(msd.times), np.asarray(msd.results.timeseries), by_group


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
