"""Viscosity tools: the Green–Kubo integral against series whose
integral is known exactly, Groot–Warren's estimate, the pressure-tensor reporter's block
averages, and a smoke run of `python3 -m openmmdpd.viscosity --quick`."""
import csv
import io
import math
import os

import numpy as np
import openmm
import pytest
from scipy.signal import lfilter
from openmm import app, unit

import openmmdpd
from openmmdpd import pressure, viscosity, viscosity_fluids
from openmmdpd.scenes import build_scene

HAS_TENSOR = hasattr(openmmdpd.DPDThermostatIntegrator, "getAveragePressureTensor")
needs_tensor = pytest.mark.skipif(not HAS_TENSOR, reason="the C++ pressure-tensor API is not built in")


# --- Green–Kubo on synthetic series -------------------------------------------------------------

def ar1(rng, phi, n, columns=3):
    """x_k = phi x_{k-1} + e_k, unit-variance noise, started from its stationary distribution:
    C(k) = phi^k / (1 - phi^2)."""
    noise = rng.standard_normal((n, columns))
    noise[0] /= math.sqrt(1 - phi**2)
    return lfilter([1.0], [1.0, -phi], noise, axis=0)


def ar1_integral(phi, interval):
    """Delta [C(0)/2 + sum_{k>=1} C(k)] = Delta C(0) (1 + phi) / (2 (1 - phi)), C(0) = 1/(1 - phi^2)."""
    return interval * (1 + phi) / (2 * (1 - phi)) / (1 - phi**2)


def test_running_integral_of_an_exact_correlation():
    phi, interval = 0.8, 0.05
    c = np.power(phi, np.arange(400)) / (1 - phi**2)
    assert viscosity.running_integral(c, interval)[-1] == pytest.approx(ar1_integral(phi, interval), rel=1e-12)
    assert viscosity.running_integral(c, interval)[0] == pytest.approx(interval * c[0] / 2)


def test_green_kubo_of_an_ar1_series_within_three_sigma():
    """600000 samples of 3 AR(1) columns (an exponential C, which the tail fit can match
    exactly): the estimate lies within 3 sigma (sigma: jackknife and spread over the fit windows,
    about 0.4 % here) of the exact integral, sigma small enough to see a 5 % error, and the scale
    multiplies it."""
    phi, interval, scale = 0.8, 0.05, 7.0
    result = viscosity.green_kubo(ar1(np.random.default_rng(5), phi, 600000), interval, scale, max_lag=200)
    exact = scale * ar1_integral(phi, interval)
    print(f"AR(1): {result['eta']:.4f} ± {result['eta_err']:.4f}, exact {exact:.4f}, tau {result['tau']:.3f}")
    assert 0 < result["eta_err"] < 0.05 * exact / 3
    assert abs(result["eta"] - exact) < 3 * result["eta_err"]
    assert result["tau"] == pytest.approx(-interval / math.log(phi), rel=0.2)


def stress_like(rng, n, tail_time=1.0, interval=0.05):
    """A series shaped like DPD's shear stress in blocks of 0.05 (the committed runs'
    C(0), its fall by 30x within 0.2 and a creep after): white noise (the random force,
    integral 0.13), a fast AR(1) (tau 0.07, 0.64) and a slow one (tail_time, 0.09, a tenth of the
    whole), scaled so that V/kT = 1; returns (series (n, 3), exact integral 0.86)."""
    def part(tau, integral):
        phi = math.exp(-interval / tau)
        return ar1(rng, phi, n) * math.sqrt(integral / ar1_integral(phi, interval))
    white = rng.standard_normal((n, 3)) * math.sqrt(2 * 0.13 / interval)
    return white + part(0.07, 0.64) + part(tail_time, 0.09), 0.86


def test_tail_fit_recovers_a_slow_tail_within_three_sigma():
    """A stress-like series with a slow tail (a tenth of the integral, tau 1), 400000 blocks:
    the tail-fit estimate lies within 3 sigma of the exact 0.86, with sigma (jackknife and
    spread over the fit windows, about 1.3 %) small enough to see a 5 % error."""
    x, exact = stress_like(np.random.default_rng(21), 400000)
    result = viscosity.green_kubo(x, 0.05, max_lag=400)
    print(f"slow tail: {result['eta']:.4f} ± {result['eta_err']:.4f} (stat {result['eta_stat']:.4f}, "
          f"sys {result['eta_sys']:.4f}), exact {exact}, tau {result['tau']:.2f}")
    assert 0 < result["eta_err"] < 0.05 * exact / 3
    assert abs(result["eta"] - exact) < 3 * result["eta_err"]


def test_shoulder_rule_reads_a_slow_tail_low_and_the_tail_fit_does_not():
    """20 stress-like series of 30000 blocks (1500 time units, the committed run's length), tail
    time 1.5: the earlier shoulder rule (shoulder_lag) averages well below the exact integral,
    more than 3 standard errors of its mean and by more than 3 %; the tail fit's mean lies within
    3 of its own (its standard error of the mean, about 1.1 %, small enough to see a 5 % error),
    and its mean reported error is within [0.6, 2] of the scatter it should describe (above 1:
    the spread over the fit windows holds some of the same noise as the jackknife; 1.5 here)."""
    rng = np.random.default_rng(22)
    results = [viscosity.green_kubo(stress_like(rng, 30000, 1.5)[0], 0.05, max_lag=400) for _ in range(20)]
    exact = 0.86
    new, old = (np.array([r[key] for r in results]) for key in ("eta", "eta_shoulder"))
    new_err, old_err = (v.std(ddof=1) / math.sqrt(len(v)) for v in (new, old))
    ratio = np.mean([r["eta_err"] for r in results]) / new.std(ddof=1)
    print(f"shoulder {old.mean():.4f} ± {old_err:.4f}, tail fit {new.mean():.4f} ± {new_err:.4f}, exact {exact}, "
          f"error / scatter {ratio:.2f}")
    assert old.mean() < exact - 3 * old_err and old.mean() < 0.97 * exact
    assert abs(new.mean() - exact) < 3 * new_err < 0.05 * exact
    assert 0.6 < ratio < 2.0


def test_exponential_tail_of_an_exact_exponential():
    """C = 0.3 exp(-t/0.8) + a fast part gone by the fit start: the fit returns the decay time
    and amplitude within the grid's 2 % spacing, and I(t0) + tail the whole integral within 1 %."""
    interval = 0.05
    t = np.arange(201) * interval
    c = 0.3 * np.exp(-t / 0.8) + 2.0 * np.exp(-t / 0.02)
    a, tau, _ = viscosity.exponential_tail(c, 20, 200, interval)
    assert tau == pytest.approx(0.8, rel=0.02) and a == pytest.approx(0.3 * math.exp(-1.0 / 0.8), rel=0.03)
    beyond = interval * 0.3 * np.exp(-t[-1] / 0.8) / (math.exp(interval / 0.8) - 1)  # the sum past the last lag
    exact = viscosity.running_integral(c, interval)[-1] + beyond
    for estimate in viscosity.tail_fit_estimates(c, interval, [(10, 200), (20, 200), (30, 100)]):
        assert estimate == pytest.approx(exact, rel=0.01)


def test_block_averaging_keeps_the_green_kubo_integral():
    """Block means of 10 samples of an AR(1) series, at 10 times the interval, integrate to the
    same value as the series itself (the zero-frequency power is unchanged), within 3 sigma."""
    phi, interval = 0.95, 0.01
    x = ar1(np.random.default_rng(9), phi, 400000)
    blocks = x.reshape(-1, 10, 3).mean(axis=1)
    result = viscosity.green_kubo(blocks, 10 * interval, max_lag=100)
    exact = ar1_integral(phi, interval)
    print(f"AR(1) in blocks of 10: {result['eta']:.4f} ± {result['eta_err']:.4f}, exact {exact:.4f}")
    assert abs(result["eta"] - exact) < 3 * result["eta_err"]
    assert result["eta_err"] < 0.05 * exact


def test_green_kubo_error_matches_the_scatter_of_independent_runs():
    """The reported error (jackknife over the segments and spread over the fit windows) is the scatter
    of the integral over 30 independent AR(1) series (their standard deviation is known to ~13 %,
    the mean error to ~5 %): the ratio is within [0.6, 1.6]."""
    rng = np.random.default_rng(10)
    results = [viscosity.green_kubo(ar1(rng, 0.5, 20000), 0.1, max_lag=40) for _ in range(30)]
    scatter = np.std([r["eta"] for r in results], ddof=1)
    ratio = np.mean([r["eta_err"] for r in results]) / scatter
    print(f"error / scatter {ratio:.2f}")
    assert 0.6 < ratio < 1.6


def test_green_kubo_keeps_the_lag_zero_half_of_white_noise():
    """White noise (a random force's stress) has C(k) = sigma^2 delta_k0: its whole integral,
    Delta sigma^2 / 2, comes from the C(0)/2 term (without it: 0; with C(0) whole: twice)."""
    sigma, interval = 3.0, 0.02
    series = sigma * np.random.default_rng(6).standard_normal((100000, 3))
    result = viscosity.green_kubo(series, interval, max_lag=50)
    exact = interval * sigma**2 / 2
    print(f"white noise: {result['eta']:.5f} ± {result['eta_err']:.5f}, exact {exact:.5f}")
    assert result["eta_err"] < 0.05 * exact
    assert abs(result["eta"] - exact) < 3 * result["eta_err"]


def test_shoulder_lag_is_where_the_integral_stops_changing():
    """The earlier shoulder rule, kept for comparison.  Segments whose integral rises by 1 per
    lag, with spread 0.1 (standard error 0.05), to lag 3 and is flat after: |I(2k) - I(k)| >
    2 sigma up to k = 2, 0 from k = 3 on: read at 6."""
    lags = np.arange(13)
    running = np.minimum(lags, 3).astype(float)
    segments = running + 0.1 * np.array([[1], [-1], [1], [-1]]) * (lags % 2)
    assert viscosity.shoulder_lag(running, segments) == 6
    assert viscosity.shoulder_lag(running + 0.1 * lags, segments) == 12  # never flat: the longest even lag


def test_autocorrelation_against_a_direct_sum():
    x = np.random.default_rng(7).standard_normal((50, 3))
    direct = [np.mean([np.mean(x[t] * x[t + k]) for t in range(50 - k)]) for k in range(6)]
    assert viscosity.autocorrelation(x, 5) == pytest.approx(direct, rel=1e-12)


def test_groot_warren_estimate():
    """docs/theory/pressure-tensor.md: 45 kT/(4 pi gamma rc^3) + 2 pi gamma rho^2 rc^5/1575, 1.08 at rho 4,
    gamma 4.5 (1.0830); 0.9573 for Groot–Warren's own fluid at rho 3."""
    estimate = viscosity_fluids.groot_warren_estimate
    assert estimate(4.0, 4.5) == pytest.approx(45 / (4 * math.pi * 4.5) + 2 * math.pi * 4.5 * 16 / 1575)
    assert round(estimate(4.0, 4.5), 2) == 1.08
    assert estimate(3.0, 4.5) == pytest.approx(0.9573, abs=1e-4)


# --- the reporter ---------------------------------------------------------------------------------

class FakeIntegrator:
    """The DPD pressure-tensor API over a known sequence of per-step tensors (part p is
    (p + 1) times the step's base tensor)."""

    def __init__(self, samples):
        self.samples, self.step_count, self.since, self.enabled = samples, 0, 0, False

    def setPressureTensorEnabled(self, enabled):
        self.enabled = enabled

    def step(self, steps):
        self.step_count += steps

    def resetPressureTensor(self):
        self.since = self.step_count

    def getAveragePressureTensor(self, part=0):
        assert self.enabled
        mean = self.samples[self.since:self.step_count].mean(axis=0) * (part + 1)
        return list(mean) * pressure.PRESSURE_UNIT


class FakeSimulation:
    """Simulation.step's reporting loop, for one reporter."""

    def __init__(self, integrator, dt=0.01):
        self.integrator, self.currentStep, self.dt = integrator, 0, dt

    def step(self, steps, reporter):
        end = self.currentStep + steps
        while self.currentStep < end:
            todo = min(reporter.describeNextReport(self)[0], end - self.currentStep)
            self.integrator.step(todo)
            self.currentStep += todo
            if self.currentStep % reporter._interval == 0:
                state = type("State", (), {"getTime": lambda s, t=self.currentStep * self.dt: t * unit.picosecond})()
                reporter.report(self, state)


def test_reporter_rows_are_block_averages():
    samples = np.random.default_rng(8).standard_normal((40, 6))
    out = io.StringIO()
    simulation = FakeSimulation(FakeIntegrator(samples))
    reporter = pressure.PressureTensorReporter(out, 10, parts=True)
    simulation.step(25, reporter)
    simulation.step(15, reporter)
    rows = list(csv.DictReader(io.StringIO(out.getvalue())))
    assert [int(r["step"]) for r in rows] == [10, 20, 30, 40]
    assert float(rows[1]["time_ps"]) == pytest.approx(0.2)
    for k, row in enumerate(rows):
        block = samples[10 * k:10 * (k + 1)].mean(axis=0)
        for p, part in enumerate(pressure.PARTS):
            prefix = "" if p == 0 else part + "_"
            got = [float(row[f"{prefix}P{c}"]) for c in pressure.COMPONENTS]
            assert got == pytest.approx(block * (p + 1), rel=1e-14)


def test_reporter_columns_without_parts():
    out = io.StringIO()
    FakeSimulation(FakeIntegrator(np.ones((5, 6)))).step(5, pressure.PressureTensorReporter(out, 5))
    assert out.getvalue().splitlines()[0] == "step,time_ps,Pxx,Pyy,Pzz,Pxy,Pxz,Pyz"


def test_reporter_refuses_bad_input():
    for interval in (0, -3, 2.5, True, "10"):
        with pytest.raises(ValueError, match="reportInterval must be an integer >= 1"):
            pressure.PressureTensorReporter(io.StringIO(), interval)
    simulation = FakeSimulation(openmm.VerletIntegrator(0.001))
    with pytest.raises(TypeError, match="needs a DPD integrator .*got VerletIntegrator"):
        pressure.PressureTensorReporter(io.StringIO(), 10).describeNextReport(simulation)


# --- with the C++ pressure tensor -------------------------------------------------------------------

def _simulation(seed=4):
    scene = build_scene("soft", num_particles=200, seed=seed)
    integrator = openmmdpd.DPDVVIntegrator(openmmdpd.KT_TEMPERATURE, 4.5, 1.0, 0.01)
    integrator.setRandomNumberSeed(seed)
    simulation = app.Simulation(scene.topology, scene.system, integrator, openmm.Platform.getPlatformByName("Reference"))
    simulation.context.setPositions(scene.positions)
    simulation.context.setVelocitiesToTemperature(openmmdpd.KT_TEMPERATURE, seed)
    return simulation


@needs_tensor
def test_reporter_block_averages_match_the_integrators_average():
    """After 5 steps already sampled, four rows of 5 steps average to what the integrator
    accumulates over the same 20 steps of an identical run (Reference platform, same seed;
    sampling leaves the trajectory unchanged), for every part: the reporter starts its own
    average and resets it after each row."""
    out = io.StringIO()
    reported = _simulation()
    reported.integrator.setPressureTensorEnabled(True)
    reported.step(5)
    reported.reporters.append(pressure.PressureTensorReporter(out, 5, parts=True))
    reported.step(20)
    rows = np.array([[float(v) for v in line.split(",")] for line in out.getvalue().splitlines()[1:]])
    assert rows[:, 0].tolist() == [10, 15, 20, 25]
    plain = _simulation()
    plain.step(5)
    plain.integrator.setPressureTensorEnabled(True)
    plain.step(20)
    assert plain.integrator.getPressureTensorSampleCount() == 20
    for part in range(len(pressure.PARTS)):
        columns = slice(2 + 6 * part, 8 + 6 * part)
        assert rows[:, columns].mean(axis=0) == pytest.approx(pressure.pressure_tensor(plain.integrator, part), rel=1e-9)


@needs_tensor
def test_viscosity_quick_smoke(tmp_path):
    out = str(tmp_path / "visc")
    viscosity.main(["--quick", "--out", out, "--quiet", "--platform", "Reference"])
    with open(os.path.join(out, "nemd.csv")) as f:
        rows = list(csv.DictReader(f))
    assert [float(r["rate"]) for r in rows] == viscosity.QUICK["rates"]
    row = rows[0]
    assert float(row["eta"]) > 0 and float(row["eta_err"]) > 0
    parts = sum(float(row[f"eta_{p}"]) for p in ("kinetic", "conservative", "thermostat"))
    assert parts == pytest.approx(float(row["eta"]), rel=1e-6)
    assert 0.8 < float(row["slope_ratio"]) < 1.2
    with open(os.path.join(out, "gk.csv")) as f:
        series = {r["series"]: r for r in csv.DictReader(f)}
    assert set(series) == {"total", "kinetic", "conservative", "thermostat", "total - thermostat"}
    for filename in ("report.md", "viscosity.png", "green_kubo.png", "temperature.png", "gk_running.csv",
                     "gk_series_model-b.npz"):
        assert os.path.getsize(os.path.join(out, filename)) > 0
    # --reanalyse reads the same numbers back from nemd.csv and the saved (float32) series
    viscosity.main(["--quick", "--out", out, "--reanalyse"])
    with open(os.path.join(out, "gk.csv")) as f:
        again = {r["series"]: r for r in csv.DictReader(f)}
    for name, row in series.items():
        assert float(again[name]["eta"]) == pytest.approx(float(row["eta"]), rel=1e-4)
    with open(os.path.join(out, "nemd.csv")) as f:
        assert float(next(csv.DictReader(f))["eta"]) == pytest.approx(float(rows[0]["eta"]))
    assert "re-read from the saved series" in open(os.path.join(out, "report.md")).read()
    # without the series, --reanalyse redraws from the CSV files and leaves them as they are
    saved = {name: open(os.path.join(out, name)).read() for name in ("gk.csv", "gk_running.csv", "nemd.csv")}
    os.remove(os.path.join(out, "gk_series_model-b.npz"))
    viscosity.main(["--quick", "--out", out, "--reanalyse"])
    assert {name: open(os.path.join(out, name)).read() for name in saved} == saved
    text = open(os.path.join(out, "report.md")).read()
    assert "re-read from the CSV files" in text and "| total | " in text and "needs the block series" in text


def test_reanalyse_reads_the_saved_series_in_either_layout(tmp_path):
    """--reanalyse redoes Green–Kubo from gk_series_SCENE.npz as runs now save it (the
    off-diagonal components alone) and as they saved it before (all six): the same gk.csv."""
    off = np.random.default_rng(23).standard_normal((2000, len(pressure.PARTS), 3)).astype(np.float32)
    tensors = np.zeros((2000, len(pressure.PARTS), 6), dtype=np.float32)
    tensors[:, :, 3:] = off
    tables = []
    for key, value in (("off_diagonal", off), ("tensors", tensors)):
        out = tmp_path / key
        out.mkdir()
        np.savez_compressed(out / "gk_series_model-a.npz", interval=0.05, volume=1000.0, kT=1.0, **{key: value})
        viscosity.main(["--out", str(out), "--reanalyse", "--scene", "model-a", "--gk-max-lag", "2"])
        tables.append((out / "gk.csv").read_text())
    assert tables[0] == tables[1] and tables[0].count("model-a") == len(pressure.PARTS) + 1


# --- the report's flags --------------------------------------------------------------------------

def nemd_row(rate, kT, kT_err, eta=1.1, eta_err=0.05, scene="model-b"):
    return dict(scene=scene, integrator="GW", dt=0.01, rate=rate, time=2.0, eta=eta, eta_err=eta_err,
                eta_kinetic=0.1, eta_conservative=0.8, eta_thermostat=0.2, Pxy=-eta * rate, Pxy_err=eta_err * rate,
                N1=0.0, N1_err=0.01, slope_ratio=1.0, slope_ratio_err=0.01, profile_rms=0.01,
                kT=kT, kT_err=kT_err, kT_x=kT, kT_y=kT, kT_z=kT)


def test_report_flags_a_peculiar_kT_off_the_target(tmp_path):
    """A --quick run measured kT 1.30: the report and the command say so; the few per cent of
    viscous heating of the committed long runs (1.025 ± 0.001 at rate 0.5) are not flagged."""
    from openmmdpd import viscosity_report as report
    rows = [nemd_row(0.05, 1.004, 0.001), nemd_row(0.2, 1.30, 0.03), nemd_row(0.5, 1.025, 0.001),
            nemd_row(1.0, 0.98, 0.05)]
    flagged = report.temperature_flags(rows)
    assert set(flagged) == {0.2, 1.0}
    assert "30% from the target 1 (10.0 standard errors), beyond the 10% tolerance" in flagged[0.2]
    assert "too few samples" in flagged[1.0]  # 3 x 0.05 is wider than the tolerance
    assert report.temperature_flags([nemd_row(0.5, 0.85, 0.2)])[0.5].startswith("peculiar kT 0.850 ± 0.200 is 15%")
    assert report.temperature_flags([nemd_row(0.5, float("nan"), float("nan"))])
    assert report.flags([nemd_row(0.05, 1.004, 0.001), nemd_row(0.5, 1.025, 0.001)], {}) == []

    args = viscosity._parser().parse_args(["--out", str(tmp_path), "--rates", "0.2"])
    args.command = ["--quick"]
    report.write_report(args, [nemd_row(0.2, 1.30, 0.03)], {}, 1.0)
    text = open(tmp_path / "report.md").read()
    assert "**1 result(s) flagged**" in text and "- **Flagged**, rate 0.2: peculiar kT 1.300 ± 0.030 is 30%" in text
    report.write_report(args, [nemd_row(0.2, 1.02, 0.003)], {}, 1.0)
    text = open(tmp_path / "report.md").read()
    assert "No result flagged" in text and "Peculiar kT within 10% of 1 at every rate" in text


def test_reanalyse_prints_the_flags(tmp_path, capsys):
    out = tmp_path / "visc"
    out.mkdir()
    with open(out / "nemd.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=viscosity.NEMD_COLUMNS)
        writer.writeheader()
        writer.writerow(nemd_row(0.5, 1.30, 0.03))
    viscosity.main(["--out", str(out), "--reanalyse"])
    assert "FLAGGED: model-b rate 0.5: peculiar kT 1.300 ± 0.030 is 30% from the target 1" in capsys.readouterr().out
