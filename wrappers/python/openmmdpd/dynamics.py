"""The main job's dynamics (docs/guide/compare.md): what DPD is run for, measured per run beside
its temperature, and judged against the same model's dt -> 0 limit.

- The transverse-current viscosity: the decay rate lambda of the transverse momentum current at
  the box's smallest wavevector k = 2 pi / L, J(t) = sum_i m_i v_i,b exp(i k x_i,a) (b != a),
  which hydrodynamics gives as exp(-nu k^2 t) with the kinematic viscosity nu = eta / rho_m, so
  eta_T = rho_m lambda / k^2.  It needs no shear and no pressure tensor, so every integrator
  has one; a Langevin thermostat damps the current at its friction gamma besides, and its
  eta_T (rho_m (gamma / k^2 + nu)) says so.
- The shear viscosity eta from a short NEMD run (Lees–Edwards shear at one rate, the
  integrator's own pressure tensor): eta = -<P_xy> / rate.
- The Schmidt number Sc = eta / (rho_m D).
- The dt -> 0 limit of each observable: a weighted least-squares fit X = X0 + b_integrator dt
  over the stable runs of the integrators that share a continuum model, at the time steps up
  to LIMIT_DT, with one intercept X0 and a slope per integrator.
- The usable region (kT within 1 %, D and eta within 5 % of their limits) and its cheapest run.
"""
import math

import numpy as np
import openmm

from .analysis import jackknife_error, standard_error

# Integrators whose dt -> 0 limit is another fluid than DPD's: Lowe-Andersen's collisions at the
# rate Gamma give the same equilibrium but other transport coefficients.  LangevinMiddleIntegrator
# has none of its own here: it is judged against DPD's limit, which it is meant to stand in for.
LIMIT_OF = {"Lowe": "Lowe-Andersen", "Lowe-mid": "Lowe-Andersen", "Langevin": None}
DPD_LIMIT = "DPD"
LIMIT_DT = 0.04          # the runs a limit is fitted over: dt <= LIMIT_DT
OBSERVABLES = ("D", "eta", "Sc", "eta_T")
USABLE_KT = 0.01         # |<kT> - 1| below this
USABLE_DYNAMICS = 0.05   # |D / D0 - 1| and |eta / eta0 - 1| below this
NEMD_BLOCK = 0.5         # time of a block average of P_xy


def limit_of(name):
    """The continuum model whose dt -> 0 limit an integrator tends to (None: none of its own)."""
    return LIMIT_OF.get(name, DPD_LIMIT)


def judged_against(name):
    """The limit an integrator's observables are divided by: its own, or DPD's."""
    return limit_of(name) or DPD_LIMIT


# --- the transverse current ------------------------------------------------------------------------

def transverse_currents(positions, velocities, masses, length):
    """The 12 real transverse currents at k = 2 pi / L: for k along each axis a, the momentum
    component b != a, real and imaginary parts.  Unwrapped positions are fine (exp is periodic)."""
    phase = np.exp(1j * (2 * np.pi / length) * np.asarray(positions))
    momenta = np.asarray(masses)[:, None] * np.asarray(velocities)
    currents = [momenta[:, b] @ phase[:, a] for a in range(3) for b in range(3) if b != a]
    return np.array([part for j in currents for part in (j.real, j.imag)])


def _autocorrelations(series, max_lag):
    """(max_lag + 1, columns): each column's autocorrelation over every time origin, unnormalised."""
    x = np.asarray(series, dtype=float)
    n = len(x)
    return np.array([(x[:n - lag] * x[lag:]).mean(axis=0) for lag in range(max_lag + 1)])


def _decay_window(c):
    """The lags 1..m over which the normalised correlation c falls to 1/e: the first e-fold, where
    the decay is best resolved (at least two lags)."""
    below = np.nonzero(c[1:] < math.exp(-1))[0]
    last = below[0] + 1 if len(below) else len(c) - 1
    return np.arange(1, max(last, 2) + 1)


def _decay_rate(c, lags, interval):
    """lambda of ln c = ln A - lambda t fitted over the lags (a free A: the stress's own short memory
    drops c a little before the hydrodynamic decay)."""
    t = lags * interval
    y = np.log(np.clip(c[lags], 1e-12, None))
    return float(-np.polyfit(t, y, 1)[0])


def _normalised(correlations):
    """The series' mean autocorrelation over their mean variance: a ratio of means (normalising each
    series first biases a run of a few decay times, here by +10 % over 17 decay times)."""
    return correlations.mean(axis=1) / correlations[0].mean()


def transverse_viscosity(series, interval, mass_density, length, max_time=20.0):
    """(eta_T, its standard error) from the transverse currents sampled every `interval`: the decay
    rate of their autocorrelation, averaged over the 12 series, over its first e-fold; the error
    is the jackknife over the series (independent modes of the fluid), each left out in turn
    with the window kept."""
    series = np.asarray(series, dtype=float)
    max_lag = max(3, min(len(series) // 4, int(max_time / interval)))
    per_series = _autocorrelations(series, max_lag)
    c = _normalised(per_series)
    lags = _decay_window(c)
    scale = mass_density * (length / (2 * np.pi)) ** 2
    left_out = [_decay_rate(_normalised(np.delete(per_series, k, axis=1)), lags, interval)
                for k in range(per_series.shape[1])]
    return scale * _decay_rate(c, lags, interval), scale * jackknife_error(left_out)


# --- NEMD ----------------------------------------------------------------------------------------

def nemd_viscosity(context, integrator, rate, equilibrate, sample, dt):
    """(eta, its standard error): the integrator, already sheared at `rate` with its pressure tensor
    on, equilibrates, then samples `sample` time in blocks of NEMD_BLOCK; the error is that of the
    block series of P_xy from its statistical inefficiency."""
    integrator.step(round(equilibrate / dt))
    steps = max(1, round(NEMD_BLOCK / dt))
    blocks = []
    for _ in range(max(2, round(sample / (steps * dt)))):
        integrator.resetPressureTensor()
        integrator.step(steps)
        pressure = integrator.getAveragePressureTensor(0)
        blocks.append(-pressure[3].value_in_unit(pressure[3].unit) / rate)
    return float(np.mean(blocks)), standard_error(blocks)


def schmidt_number(eta, eta_err, d, d_err, mass_density):
    """(Sc, its error) = eta / (rho_m D), the errors independent."""
    if not (math.isfinite(eta) and math.isfinite(d) and d > 0):
        return float("nan"), float("nan")
    sc = eta / (mass_density * d)
    return sc, abs(sc) * math.hypot(eta_err / eta, d_err / d)


# --- limits ----------------------------------------------------------------------------------------

def _limit_points(rows, key, limit, max_dt):
    points = [(row["integrator"], row["dt"], row[key], row[key + "_err"]) for row in rows
              if row["status"] == "ok" and limit_of(row["integrator"]) == limit and row["dt"] <= max_dt
              and math.isfinite(row[key]) and math.isfinite(row[key + "_err"]) and row[key + "_err"] > 0]
    # a slope needs two time steps: an integrator with one stable dt in range says nothing of the limit
    counts = {}
    for name, *_ in points:
        counts[name] = counts.get(name, 0) + 1
    return [p for p in points if counts[p[0]] > 1]


def extrapolate(rows, key, limit=DPD_LIMIT, max_dt=LIMIT_DT):
    """{value, error, runs, integrators, chi2_dof} of X0 in X = X0 + b_integrator dt, weighted least
    squares over the stable runs of the integrators whose limit is `limit` at dt <= max_dt; the
    error from the fit's covariance, scaled by sqrt(chi^2 / dof) where that is above 1 (the
    integrators' errors then do not cover their scatter about straight lines).  None with fewer
    runs than parameters plus one."""
    points = _limit_points(rows, key, limit, max_dt)
    names = sorted({p[0] for p in points})
    if len(points) < len(names) + 2:
        return None
    design = np.array([[1.0] + [dt if name == n else 0.0 for n in names] for name, dt, _, _ in points])
    weights = np.array([1 / err for *_, err in points])
    values = np.array([value for _, _, value, _ in points])
    a, b = design * weights[:, None], values * weights
    solution, *_ = np.linalg.lstsq(a, b, rcond=None)
    chi2_dof = float(np.sum((a @ solution - b) ** 2) / (len(points) - len(names) - 1))
    covariance = np.linalg.inv(a.T @ a) * max(1.0, chi2_dof)
    return dict(value=float(solution[0]), error=float(np.sqrt(covariance[0, 0])), runs=len(points),
                integrators=names, chi2_dof=chi2_dof)


def limits(rows):
    """{(limit, key): extrapolate(...)} for every limit the rows' integrators tend to and every observable."""
    found = {limit_of(row["integrator"]) for row in rows} - {None}
    return {(limit, key): extrapolate(rows, key, limit) for limit in sorted(found) for key in OBSERVABLES}


def relative_to_limits(rows, fitted):
    """Puts X_rel = X / X0 and its error (both errors) in every row, X0 the limit it is judged against."""
    for row in rows:
        for key in OBSERVABLES:
            limit = fitted.get((judged_against(row["integrator"]), key))
            row[key + "_rel"] = row[key + "_rel_err"] = float("nan")
            if limit and math.isfinite(row[key]):
                ratio = row[key] / limit["value"]
                row[key + "_rel"] = ratio
                row[key + "_rel_err"] = abs(ratio) * math.hypot(row[key + "_err"] / row[key],
                                                                limit["error"] / limit["value"])


def usable(row):
    """A stable run whose <kT> is within USABLE_KT of 1 and whose D and eta are within
    USABLE_DYNAMICS of their limits (a run without eta is not shown to be usable)."""
    return (row["status"] == "ok" and row["kT_error"] < USABLE_KT
            and all(math.isfinite(row[key + "_rel"]) and abs(row[key + "_rel"] - 1) < USABLE_DYNAMICS
                    for key in ("D", "eta")))


def recommend(rows):
    """The cheapest usable run (the lowest cost per unit of simulated time), or None."""
    candidates = [row for row in rows if usable(row) and math.isfinite(row["cost_per_time"])]
    return min(candidates, key=lambda row: row["cost_per_time"], default=None)


def sheared_integrator(integrator_factory, dt, rate, seed, threshold=0.0):
    """A new integrator sheared at `rate` with its pressure tensor on; an integrator without them
    refuses here (OpenMMException), before any Context."""
    integrator = integrator_factory(dt)
    integrator.setRandomNumberSeed(seed)
    if threshold:
        integrator.setInstabilityThreshold(threshold)
    integrator.setShearRate(rate)
    integrator.setPressureTensorEnabled(True)
    return integrator


def sheared_context(system, state, integrator, rate, platform):
    """A Context of the sheared integrator at `state` (taken with enforcePeriodicBox, molecules
    whole in the box): its positions, and its velocities plus the imposed flow rate (y - Ly/2)."""
    from .shear import impose_flow
    sheared = openmm.Context(system, integrator, *platform)
    sheared.setPeriodicBoxVectors(*state.getPeriodicBoxVectors())
    sheared.setPositions(state.getPositions())
    sheared.setVelocities(state.getVelocities())
    impose_flow(sheared, rate)
    return sheared
