"""The bench's paired measurements run and print one row per integrator, size and thread count."""
from openmmdpd import bench


def test_shear_cost_is_measured_for_each_integrator(capsys):
    bench.main(["--shear", "0.1", "--integrators", "GW", "S1", "--sizes", "500", "--threads", "1",
                "--seconds", "0.02", "--repeats", "1", "--warmup", "2"])
    rows = [line.split() for line in capsys.readouterr().out.splitlines()[2:]]
    assert [row[:3] for row in rows] == [["GW", "500", "1"], ["S1", "500", "1"]]
    assert all(float(row[3]) > 0 and float(row[4]) > 0 for row in rows)


def test_sentinel_cost_is_measured(capsys):
    bench.main(["--sentinel", "--sizes", "500", "--threads", "1", "--seconds", "0.02", "--repeats", "1", "--warmup", "2"])
    rows = capsys.readouterr().out.splitlines()[2:]
    assert len(rows) == 1 and rows[0].split()[:3] == ["GW", "500", "1"]
