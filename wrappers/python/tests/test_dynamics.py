"""The main job's dynamics (openmmdpd.dynamics): the transverse-current viscosity against exact
currents and an exactly known decay, the dt -> 0 limit against exact lines, and the usable
region's recommendation following the numbers it is given."""
import argparse
import math

import numpy as np
import pytest
from scipy.signal import lfilter

from openmmdpd import dynamics, report_dynamics


def test_transverse_currents_of_a_shear_wave_are_exact():
    # v_y = A cos(k x) on a lattice of whole periods: J_y(k x) = A N / 2 (real), every other current 0
    length, amplitude = 5.0, 0.3
    grid = (np.arange(10) + 0.25) * length / 10
    positions = np.array([(x, y, z) for x in grid for y in grid for z in grid])
    velocities = np.zeros_like(positions)
    velocities[:, 1] = amplitude * np.cos(2 * np.pi * positions[:, 0] / length)
    currents = dynamics.transverse_currents(positions, velocities, np.full(len(positions), 2.0), length)
    expected = np.zeros(12)
    expected[0] = 2.0 * amplitude * len(positions) / 2  # k along x, momentum along y, real part
    assert currents == pytest.approx(expected, abs=1e-9)
    # a whole box shift changes no current's magnitude
    shifted = dynamics.transverse_currents(positions + length, velocities, np.full(len(positions), 2.0), length)
    assert shifted == pytest.approx(currents, abs=1e-9)


def ornstein_uhlenbeck(rate, interval, samples, series, seed):
    """Independent stationary series with the exact autocorrelation exp(-rate t)."""
    rng = np.random.default_rng(seed)
    decay = math.exp(-rate * interval)
    noise = rng.standard_normal((samples, series)) * math.sqrt(1 - decay ** 2)
    noise[0] = rng.standard_normal(series)
    return lfilter([1.0], [1.0, -decay], noise, axis=0)  # x_k = decay x_(k-1) + noise_k


def test_transverse_viscosity_reads_an_exact_decay_rate():
    # currents that decay exactly at nu k^2: eta_T = rho nu within 3 sigma, and sigma small enough to see 1 %
    length, mass_density, eta = 8.0, 4.0, 1.1
    rate = eta / mass_density * (2 * np.pi / length) ** 2 * 8  # 8x the fluid's: more decays per sample
    series = ornstein_uhlenbeck(rate, 0.1, 640000, 12, seed=3)
    value, error = dynamics.transverse_viscosity(series, 0.1, mass_density, length, max_time=3.0)
    assert error < 0.0033 * 8 * eta
    assert abs(value - 8 * eta) < 3 * error


def test_transverse_viscosity_of_short_runs_is_nearly_unbiased():
    # 3000 runs of 12 series, each 17 decay times long, as a 100-unit run of model B: the mean of
    # their eta_T (sigma 0.3 %) is within 2 % + 3 sigma of the exact value. Normalising each series
    # before averaging, which this guards against, reads +10 %; the ratio of means leaves about +1 %.
    runs, samples, interval, rate = 3000, 170, 0.1, 1.0
    series = ornstein_uhlenbeck(rate, interval, samples, 12 * runs, seed=5)
    values = np.array([dynamics.transverse_viscosity(series[:, 12 * k:12 * (k + 1)], interval, 1.0, 2 * np.pi)[0]
                       for k in range(runs)])
    sigma = values.std(ddof=1) / math.sqrt(runs)
    assert sigma < 0.0033
    assert abs(values.mean() - rate) < 0.02 + 3 * sigma


def line_rows(limit=2.0, slopes=None, error=0.01, dts=(0.02, 0.03, 0.04)):
    slopes = slopes or {"GW": 3.0, "S1": -1.0, "PairOU": 0.5}
    rows = []
    for name, slope in slopes.items():
        for dt in dts:
            rows.append(dict(integrator=name, dt=dt, status="ok", D=limit + slope * dt, D_err=error))
    return rows


def test_the_limit_of_exact_lines_is_their_common_intercept():
    rows = line_rows()
    rows.append(dict(integrator="S2", dt=0.02, status="ok", D=5.0, D_err=0.01))  # one dt: no slope, left out
    rows.append(dict(integrator="GW", dt=0.06, status="ok", D=9.0, D_err=0.01))  # beyond LIMIT_DT
    rows.append(dict(integrator="GW", dt=0.01, status="unstable", D=9.0, D_err=0.01))
    rows.append(dict(integrator="Lowe", dt=0.02, status="ok", D=9.0, D_err=0.01))  # another model
    fit = dynamics.extrapolate(rows, "D")
    assert fit["value"] == pytest.approx(2.0, abs=1e-12)
    assert fit["integrators"] == ["GW", "PairOU", "S1"] and fit["runs"] == 9
    # the error is that of the fit: one intercept and three slopes from nine points of error 0.01
    assert 0.01 < fit["error"] < 0.05
    assert dynamics.extrapolate(line_rows(dts=(0.02,)), "D") is None


def test_a_scatter_beyond_the_errors_widens_the_limits_error():
    exact = dynamics.extrapolate(line_rows(), "D")
    rows = line_rows()
    for k, row in enumerate(rows):
        row["D"] += 0.05 * (-1) ** k  # five times the stated error
    scattered = dynamics.extrapolate(rows, "D")
    assert scattered["chi2_dof"] > 4
    assert scattered["error"] > 2 * exact["error"]


def table(changes=None):
    """A synthetic comparison: the cheapest run is GW at dt 0.04; (name, dt): {column: value} changes it."""
    rows = []
    for name, costs in (("GW", (50, 33, 25)), ("S1", (60, 40, 30)), ("Langevin", (40, 27, 20))):
        for dt, cost in zip((0.02, 0.03, 0.04), costs):
            rows.append(dict(integrator=name, dt=dt, status="ok", kT=1.001, kT_err=0.001, kT_error=0.001,
                             cost_per_time=cost, cost_per_time_err=1.0, D=0.27, D_err=0.003, D_rel=1.01,
                             D_rel_err=0.02, eta=1.1, eta_err=0.02, eta_rel=1.02, eta_rel_err=0.02, usable=1))
    for row in rows:
        row.update((changes or {}).get((row["integrator"], row["dt"]), {}))
        if row["integrator"] == "Langevin":
            row.update(D_rel=0.45, eta=math.nan, eta_rel=math.nan)
    return rows


def test_the_recommendation_is_the_cheapest_usable_run_and_follows_the_numbers():
    assert (dynamics.recommend(table())["integrator"], dynamics.recommend(table())["dt"]) == ("GW", 0.04)
    assert "**GW at dt 0.04**" in report_dynamics.recommendation(table(), "soft")
    # the next, S1 at 0.04 (30 +- 1 against 25 +- 1), is told apart; at 26 +- 1 it is not, and the report says so
    assert "Next: S1 at dt 0.04 (30 ± 1)." in report_dynamics.recommendation(table(), "soft")
    close = report_dynamics.recommendation(table({("S1", 0.04): dict(cost_per_time=26)}), "soft")
    assert "Next: S1 at dt 0.04 (26 ± 1), as cheap within the timings' errors (0.7 sigma apart)" in close
    # GW's largest dt now diffuses 6 % too fast: S1 at 0.04 (30) is cheaper than GW at 0.03 (33)
    moved = dynamics.recommend(table({("GW", 0.04): dict(D_rel=1.06)}))
    assert (moved["integrator"], moved["dt"]) == ("S1", 0.04)
    # ... or runs 1.5 % hot; or its viscosity is off; or it is unstable
    for change in (dict(kT_error=0.015), dict(eta_rel=0.94), dict(eta_rel=math.nan), dict(status="unstable")):
        moved = dynamics.recommend(table({("GW", 0.04): change}))
        assert (moved["integrator"], moved["dt"]) == ("S1", 0.04), change
    # Langevin is cheapest but never usable: its D is a friction-dominated fluid's, and it has no eta
    assert all(row["integrator"] != "Langevin" for row in table() if dynamics.usable(row))
    nothing = table({(name, dt): dict(D_rel=1.2) for name in ("GW", "S1") for dt in (0.02, 0.03, 0.04)})
    assert dynamics.recommend(nothing) is None
    assert "No run on scene soft is usable" in report_dynamics.recommendation(nothing, "soft")


def test_schmidt_number_and_its_error():
    sc, error = dynamics.schmidt_number(1.2, 0.012, 0.3, 0.003, 4.0)
    assert sc == pytest.approx(1.0)
    assert error == pytest.approx(math.sqrt(2) * 0.01)
    assert math.isnan(dynamics.schmidt_number(math.nan, 0.0, 0.3, 0.003, 4.0)[0])


def test_independent_values_are_used_only_for_their_own_model(tmp_path):
    diffusion, viscosity = tmp_path / "results.csv", tmp_path / "nemd.csv"
    diffusion.write_text("scene,integrator,dt,status,steps,D,D_err\nsoft,S1,0.005,ok,200000,0.2713,0.0012\n")
    viscosity.write_text("scene,integrator,dt,rate,time,eta,eta_err\nmodel-b,S1,0.005,0.5,1000,1.0985,0.0042\n")
    args = argparse.Namespace(scene="soft", a=25.0, nemd_rate=0.5, reference_diffusion=str(diffusion),
                              reference_viscosity=str(viscosity))
    found = report_dynamics._independent(args)
    assert found["D"][:2] == (0.2713, 0.0012) and found["eta"][:2] == (1.0985, 0.0042)
    assert "eta" not in report_dynamics._independent(argparse.Namespace(**{**vars(args), "nemd_rate": 0.2}))
    for other in (dict(scene="ideal"), dict(scene="polymer"), dict(a=18.75)):
        assert report_dynamics._independent(argparse.Namespace(**{**vars(args), **other})) == {}
