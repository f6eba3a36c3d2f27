"""A fast smoke run of the main job: columns, files, and an unstable dt recorded as such."""
import csv
import os

import pytest

from openmmdpd import compare


def test_compare_smoke_run(tmp_path):
    out = str(tmp_path / "cmp")
    compare.main(["--scene", "soft", "--particles", "250", "--steps", "60", "--equilibrate", "150",
                  "--stride", "10", "--frame-every", "2", "--dts", "0.02", "3.0",
                  "--integrators", "GW", "S1", "Lowe", "--threads", "1", "--out", out, "--quiet"])
    with open(os.path.join(out, "results.csv")) as f:
        reader = csv.DictReader(f)
        assert reader.fieldnames == compare.COLUMNS
        rows = {(row["integrator"], float(row["dt"])): row for row in reader}
    assert len(rows) == 6
    # A deliberately unstable dt is a recorded data point, not a crash.
    assert rows[("GW", 3.0)]["status"] == "unstable"
    assert "blew up at step" in rows[("GW", 3.0)]["note"]
    assert rows[("S1", 3.0)]["status"] == "unstable"
    assert rows[("Lowe", 3.0)]["status"] == "invalid"  # Gamma dt > 1 is refused up front
    for name in ("GW", "S1", "Lowe"):
        row = rows[(name, 0.02)]
        assert row["status"] == "ok"
        assert 0.7 < float(row["kT"]) < 1.3
        assert float(row["cpu_s_per_time"]) > 0
    for filename in ("report.md", "kT_vs_dt.png", "error_vs_cost.png", "gr.png", "diffusion.png", "stability.png"):
        assert os.path.getsize(os.path.join(out, filename)) > 0
    report = open(os.path.join(out, "report.md")).read()
    assert "| GW | 0.02 | 0.02 |" in report or "| GW | 0.02 |" in report
    assert "above 40 kT" in report  # the instability sentinel is on by default


def test_compare_records_a_transient_blow_up_as_unstable(tmp_path):
    # Polymer at dt = 0.03 with this seed: a chain bead passes 40 kT at step 168 (GW), a
    # transient event the run would otherwise go through and average over.
    def run(*extra):
        out = str(tmp_path / f"cmp{len(extra)}")
        compare.main(["--scene", "polymer", "--particles", "500", "--steps", "200", "--equilibrate", "0",
                      "--stride", "10", "--dts", "0.03", "--integrators", "GW", "--threads", "1", "--seed", "29",
                      "--out", out, "--quiet", *extra])
        with open(os.path.join(out, "results.csv")) as f:
            return next(csv.DictReader(f))
    row = run()
    assert row["status"] == "unstable" and "unstable at step 168: particle 14" in row["note"]
    assert run("--instability-threshold", "0")["status"] == "ok"


def test_help_describes_the_job_in_whole_sentences(capsys):
    with pytest.raises(SystemExit):
        compare.main(["--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "over a sweep of time steps, measured for accuracy and for cost in the same run, with charts, " \
           "the CSV behind them and a report." in text
