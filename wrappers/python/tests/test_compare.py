"""The main job: a fast smoke run (columns, files, unstable runs recorded with their reason),
its stability criteria, standard errors and coordination numbers against exact values."""
import csv
import os

import numpy as np
import pytest

from openmmdpd import analysis, catalog, charts, compare, report


def test_compare_smoke_run(tmp_path):
    out = str(tmp_path / "cmp")
    compare.main(["--quick", "--dts", "0.02", "0.1", "3.0", "--integrators", "GW", "S1", "Lowe", "--threads", "1",
                  "--out", out, "--quiet"])
    with open(os.path.join(out, "results.csv")) as f:
        reader = csv.DictReader(f)
        assert reader.fieldnames == compare.COLUMNS
        rows = {(row["integrator"], float(row["dt"])): row for row in reader}
    assert len(rows) == 9
    # A deliberately unstable dt is a recorded data point, not a crash.
    assert rows[("GW", 3.0)]["status"] == "unstable" and rows[("GW", 3.0)]["reason"] == "blow-up"
    assert "blew up at step" in rows[("GW", 3.0)]["note"]
    # Lowe at dt 0.1 keeps <kT> near 1 but its configurations are at kT ~ 1.8 (model B: 1.79).
    assert rows[("Lowe", 0.1)]["status"] == "unstable" and rows[("Lowe", 0.1)]["reason"] == "kT_conf"
    assert 0.9 < float(rows[("Lowe", 0.1)]["kT"]) < 1.1
    assert rows[("S1", 3.0)]["status"] == "unstable"
    assert rows[("Lowe", 3.0)]["status"] == "invalid"  # Gamma dt > 1 is refused up front
    for name in ("GW", "S1", "Lowe"):
        row = rows[(name, 0.02)]
        assert row["status"] == "ok"
        assert 0.7 < float(row["kT"]) < 1.3
        assert float(row["cpu_s_per_time"]) > 0
        assert float(row["cost_ratio"]) > 0 and float(row["cost_ratio_err"]) >= 0
        assert float(row["cost_per_time"]) == pytest.approx(float(row["cost_ratio"]) / 0.02)
        for column in ("kT_err", "kT_conf_err", "r1_err", "Nc_err", "Nc_1.0_err", "Nc_1.16_err"):
            assert float(row[column]) > 0, column
        assert float(row["Nc_1.0"]) < float(row["Nc_1.16"])
        # the dynamics: eta from a sheared run, Sc, eta_T from the transverse currents, all with errors
        for column in ("D", "eta", "Sc", "eta_T"):
            assert float(row[column]) > 0 and float(row[column + "_err"]) > 0, column
    assert float(rows[("Lowe", 0.02)]["D"]) < 0.5 * float(rows[("GW", 0.02)]["D"])  # Lowe-Andersen at Gamma 4.5
    for filename in ("report.md", "kT_vs_dt.png", "error_vs_cost.png", "gr.png", "dynamics_vs_dt.png",
                     "dynamics_vs_cost.png", "stability.png"):
        assert os.path.getsize(os.path.join(out, filename)) > 0
    report = open(os.path.join(out, "report.md")).read()
    assert "| GW | 0.02 | 0.02 |" in report or "| GW | 0.02 |" in report
    assert "above 40 kT" in report  # the instability sentinel is on by default
    assert "| Lowe | 0.1 | unstable (kT_conf) |" in report
    assert "LangevinMiddleIntegrator steps per unit of simulated time" in report
    assert "## Dynamics" in report and "### dt -> 0 limits" in report
    # --redraw, with the run's options, writes the same report from the CSV files
    os.remove(os.path.join(out, "gr.png"))
    compare.main(["--quick", "--threads", "1", "--out", out, "--redraw"])
    assert open(os.path.join(out, "report.md")).read() == report
    assert os.path.getsize(os.path.join(out, "gr.png")) > 0
    with pytest.raises(SystemExit, match="give the options the run was made with"):
        compare.main(["--quick", "--time", "5", "--out", out, "--redraw"])


def test_every_integrator_has_a_colour_and_a_marker_of_its_own():
    from matplotlib.colors import to_hex
    names = set(catalog.integrators("soft")) | {"OpenMM-DPD"}
    assert names <= set(charts.INTEGRATOR_STYLES)
    styles = [charts.integrator_style(name) for name in charts.INTEGRATOR_STYLES]
    assert len({to_hex(style["color"]) for style in styles}) == len(styles)
    assert len({style["marker"] for style in styles}) == len(styles)
    assert "x" not in {style["marker"] for style in styles}  # the unstable runs' cross


def test_quick_preset_sets_defaults_that_explicit_options_override(monkeypatch):
    seen = {}
    monkeypatch.setattr(compare, "compare", lambda args: seen.update(vars(args)) or [])
    compare.main(["--quick", "--time", "7", "--out", "x"])
    assert (seen["particles"], seen["time"], seen["dts"]) == (compare.QUICK["particles"], 7.0, compare.QUICK["dts"])
    compare.main(["--out", "x"])
    assert seen["particles"] == 2000 and seen["time"] > compare.QUICK["time"]


def test_compare_records_a_transient_blow_up_as_unstable(tmp_path):
    # Polymer at dt = 0.03 with this seed: a chain bead passes 40 kT at step 168 (GW), a
    # transient event the run would otherwise go through and average over.
    def run(*extra):
        out = str(tmp_path / f"cmp{len(extra)}")
        compare.main(["--scene", "polymer", "--particles", "500", "--time", "6", "--equilibrate", "0", "--prepare", "0",
                      "--sample-every", "0.3", "--dts", "0.03", "--integrators", "GW", "--threads", "1", "--seed", "29",
                      "--cost-block", "0.01", "--cost-repeats", "2", "--out", out, "--quiet", *extra])
        with open(os.path.join(out, "results.csv")) as f:
            return next(csv.DictReader(f))
    row = run()
    assert row["status"] == "unstable" and "unstable at step 168: particle 14" in row["note"]
    assert row["reason"] == "sentinel"
    # Without the sentinel the run goes through the event, and the polymer's own criteria catch it:
    # its chain <kT> is 1.36 ± 0.22 and a bond reached 2.74.
    row = run("--instability-threshold", "0")
    assert row["steps"] == "200" and row["status"] == "unstable" and row["reason"] == "chain_kT"
    assert float(row["chain_kT_err"]) > 0 and float(row["Rg_err"]) > 0  # the polymer's own series
    assert float(row["bond_max"]) > compare.BOND_LIMIT


def test_help_describes_the_job_in_whole_sentences(capsys):
    with pytest.raises(SystemExit):
        compare.main(["--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "over a sweep of time steps, measured for accuracy and for cost in the same run, with charts, " \
           "the CSV behind them and a report." in text


# --- standard errors ------------------------------------------------------------------------

def test_standard_error_of_a_correlated_series_matches_the_exact_variance_of_the_mean():
    # AR(1) x_t = phi x_(t-1) + e_t, started stationary: Var(mean) = var_x / n (1 + 2 sum_k (1 - k/n) phi^k)
    # exactly (tau ~ 10 samples here, so a naive var/n would be 19 times too small).
    from scipy.signal import lfilter
    phi, n, series = 0.9, 2000, 100
    rng = np.random.default_rng(1)
    start = rng.standard_normal((series, 1)) * phi / np.sqrt(1 - phi ** 2)
    x = lfilter([1.0], [1.0, -phi], rng.standard_normal((series, n)), axis=1, zi=start)[0]
    k = np.arange(1, n)
    exact = 1 / (1 - phi ** 2) / n * (1 + 2 * np.sum((1 - k / n) * phi ** k))
    estimates = np.array([analysis.standard_error(s) ** 2 for s in x])
    sigma = estimates.std(ddof=1) / np.sqrt(series)  # ~2.7 % of exact (pymbar's bias: about +3 %)
    assert abs(estimates.mean() - exact) < 3 * sigma
    assert analysis.standard_error(np.ones(10)) == 0.0


def test_ratio_error_is_that_of_the_linearised_ratio():
    rng = np.random.default_rng(2)
    b = 10 + rng.standard_normal(4000)
    a = 2 * b + 0.5 * rng.standard_normal(4000)  # a / b = 2 plus independent noise of 0.5 / 10
    ratio, error = analysis.ratio_with_error(a, b)
    assert abs(ratio - 2) < 3 * error
    # rel 0.1: a standard deviation from 4000 samples is good to 1.1 %; pymbar's g >= 1 adds up to a few %.
    assert error == pytest.approx(0.5 / 10 / np.sqrt(4000), rel=0.1)


# --- coordination numbers -------------------------------------------------------------------

def test_coordination_number_at_a_fixed_radius_is_exact_on_the_ideal_gas():
    # Uniform independent particles in a periodic box: the pairs within R are pairwise
    # uncorrelated, so pairs ~ M p (1 - p) in variance, M = n(n-1)/2, p = 4/3 pi R^3 / V, and
    # Nc = 2 pairs / (n - 1) per frame, mean 4/3 pi R^3 rho.
    n, density, frames = 1000, 3.0, 40  # sigma(Nc(1.16)) = 0.03, 0.16 % of it
    length = (n / density) ** (1 / 3)
    rng = np.random.default_rng(3)
    r, frame_g = analysis.frame_radial_distributions(rng.uniform(0, length, (frames, n, 3)), length,
                                                     *compare.g_r_range(length))
    g, shells = compare.shell_structure(r, frame_g, density)
    for radius in compare.FIXED_RADII:
        p = 4 / 3 * np.pi * radius ** 3 / length ** 3
        sigma = 2 / (n - 1) * np.sqrt(n * (n - 1) / 2 * p * (1 - p) / frames)
        assert abs(shells[f"Nc_{radius}"] - 4 / 3 * np.pi * radius ** 3 * density) < 3 * sigma
        assert 0 < shells[f"Nc_{radius}_err"] < 2 * sigma
    assert np.isnan(shells["r1"]) and np.isnan(shells["Nc"])  # no shell structure to find


def test_first_minimum_and_coordination_number_of_a_model_g():
    # A first peak at 0.85 and a Gaussian dip centred at 1.3; g = 2 throughout has Nc(R) = 2 * 4/3 pi R^3 rho
    # to any R, in the middle of a bin (1.16) or on an edge (1.0).
    r = (np.arange(80) + 0.5) * 0.025
    g = np.where(r < 0.6, 0.0, 1 + 1.5 * np.exp(-((r - 0.85) / 0.1) ** 2) - 0.5 * np.exp(-((r - 1.3) / 0.15) ** 2))
    assert compare.first_minimum(r, g) == pytest.approx(1.3, abs=0.03)
    for radius in (1.0, 1.16):
        assert compare.coordination_at(r, np.full(80, 2.0), radius, 3.0) == pytest.approx(8 / 3 * np.pi * radius ** 3 * 3.0)


# --- stability --------------------------------------------------------------------------------

def _row(dt=0.01, kT=1.0, kT_conf=1.0, g_core=0.02, name="GW", chain_kT=1.0, bond_max=1.5):
    return dict(integrator=name, dt=dt, status="ok", reason="", note="", kT=kT, kT_conf=kT_conf, g_core=g_core,
                chain_kT=chain_kT, bond_max=bond_max)


def test_each_stability_criterion_can_fail_a_run():
    assert compare.failure_reason("GW: the simulation blew up at step 3: a velocity is not finite") == "blow-up"
    assert compare.failure_reason("kinetic temperature 13.9 at step 10") == "blow-up"
    assert compare.failure_reason("GW: the simulation is unstable at step 168: particle 14 has kinetic energy "
                                  "41 kT, above the instability threshold 40 kT.") == "sentinel"
    for kwargs, scene, reason in [(dict(kT=1.6), "soft", "kT"), (dict(kT=0.4), "ideal", "kT"),
                                  (dict(kT_conf=1.12), "soft", "kT_conf"), (dict(kT_conf=0.88), "soft", "kT_conf"),
                                  (dict(kT_conf=1.12), "ideal", ""), (dict(kT_conf=1.08), "soft", ""),
                                  (dict(chain_kT=1.12), "polymer", "chain_kT"), (dict(chain_kT=0.88), "polymer", "chain_kT"),
                                  (dict(chain_kT=1.08, bond_max=2.4), "polymer", ""), (dict(chain_kT=1.2), "soft", ""),
                                  (dict(bond_max=2.6), "polymer", "bond"), (dict(bond_max=2.6), "soft", "")]:
        row = _row(**kwargs)
        compare.judge(row, scene)
        assert (row["status"], row["reason"]) == ("unstable" if reason else "ok", reason), kwargs
    # Overlap: against the median g(r < 0.2) of the smallest dt's stable runs (0.02, not the outlier 0.9).
    rows = [_row(g_core=0.02), _row(g_core=0.03, name="S1"), _row(g_core=0.9, name="Lowe"),
            _row(dt=0.1, g_core=0.2), _row(dt=0.1, g_core=0.4, name="S1"),
            _row(dt=0.15, g_core=1.0, name="Lowe", kT=2.0)]
    compare.judge(rows[-1], "soft")
    compare.judge_overlaps(rows)
    assert [row["reason"] for row in rows] == ["", "", "overlap", "", "overlap", "kT"]


def test_points_under_three_standard_errors_are_below_the_noise_floor():
    assert report.below_noise_floor({"kT_error": 0.0059, "kT_err": 0.002})
    assert not report.below_noise_floor({"kT_error": 0.0061, "kT_err": 0.002})


# --- cost and MSD -----------------------------------------------------------------------------

def test_median_error_matches_the_spread_of_medians():
    # 7 normal values per median, as the cost's 7 repeats: the error estimated from each draw's MAD against
    # the true scatter of the medians over 20000 draws. The MAD of 7 values is biased low by about 9 %
    # (the estimator is asymptotic); allowed 12 %. Without the factor 1.2533 it would read 27 % low.
    rng = np.random.default_rng(5)
    draws = rng.standard_normal((20000, 7))
    truth = np.median(draws, axis=1).std()
    estimated = np.mean([analysis.median_with_error(x)[1] for x in draws])
    assert estimated == pytest.approx(truth, rel=0.12)
    assert analysis.median_with_error([1.0, 2.0, 9.0])[0] == 2.0  # robust: the outlier does not move it


def test_diffusion_of_a_random_walk_from_the_library_msd():
    # Gaussian steps of variance s^2 per axis per frame: MSD(lag) = 3 s^2 lag exactly, D = s^2 / (2 frame time).
    # sigma of D from 20 independent walks of 500 particles each (the test's own scatter).
    rng = np.random.default_rng(6)
    s, frame_time, frames = 0.2, 0.5, 40
    estimates = [compare.diffusion(*analysis.mean_squared_displacement(
        np.cumsum(rng.normal(0, s, (frames, 500, 3)), axis=0), frame_time)) for _ in range(20)]
    sigma = np.std(estimates, ddof=1) / np.sqrt(len(estimates))
    assert 0 < sigma < 0.01 * s ** 2 / (2 * frame_time)
    assert abs(np.mean(estimates) - s ** 2 / (2 * frame_time)) < 3 * sigma


def test_error_of_diffusion_is_the_scatter_between_independent_walks():
    # 60 independent walks: the mean of D's estimated error against the observed scatter of D.
    # Their ratio has sigma ~0.1 (the scatter from 60 values, the estimates from 8 groups each),
    # so 0.3 is 3 sigma; a missing sqrt(groups) (factor 2.8) fails it.
    rng = np.random.default_rng(7)
    s, frame_time, frames = 0.2, 0.5, 40
    results = [compare.diffusion_with_error(*analysis.grouped_squared_displacement(
        np.cumsum(rng.normal(0, s, (frames, 400, 3)), axis=0), frame_time, compare.DIFFUSION_GROUPS))
        for _ in range(60)]
    estimates, errors = np.array(results).T
    assert np.mean(errors) / np.std(estimates, ddof=1) == pytest.approx(1, abs=0.3)
