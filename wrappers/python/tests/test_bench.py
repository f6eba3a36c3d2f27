"""The bench's modes run and print one row per integrator, size and thread count; scale's
ratios agree with its rates; memory reads a Context's resident memory."""
import argparse
import queue
import threading

import numpy as np
import pytest
from pytest import approx

from openmmdpd import bench, bench_copies, bench_memory, bench_rates, bench_scale, bench_threads, bench_timing


def test_rates_table_against_langevin_and_the_soft_force_table(capsys):
    bench.main(["rates", "--integrators", "GW", "Langevin", "--sizes", "500", "--threads", "1", "--seconds", "0.02",
                "--repeats", "1", "--warmup", "2", "--soft-force"])
    lines = capsys.readouterr().out.splitlines()
    rows = [line.split() for line in lines[2:4]]
    assert [row[:3] for row in rows] == [["500", "1", "GW"], ["500", "1", "Langevin"]]
    assert float(rows[0][3]) > 0 and rows[1][4] == "1.00"
    assert lines[6].split()[:4] == ["N", "threads", "what", "per"]
    assert [line.split(",")[0].split()[2:] for line in lines[7:]] == [["force", "only"], ["GW", "step"]] * 2


def test_shear_cost_is_measured_for_each_integrator(capsys):
    bench.main(["shear", "--rate", "0.1", "--integrators", "GW", "S1", "--sizes", "500", "--threads", "1",
                "--seconds", "0.02", "--repeats", "1", "--warmup", "2"])
    rows = [line.split() for line in capsys.readouterr().out.splitlines()[2:]]
    assert [row[:3] for row in rows] == [["GW", "500", "1"], ["S1", "500", "1"]]
    assert all(float(row[3]) > 0 and float(row[4]) > 0 for row in rows)


def test_shear_runs_with_its_default_integrators(capsys):
    """Without --integrators, shear takes the rates mode's that can shear: not Langevin, which
    has no shear rate, and OC with the soft scene's averages."""
    bench.main(["shear", "--rate", "0.1", "--sizes", "500", "--threads", "1", "--seconds", "0.02", "--repeats", "1",
                "--warmup", "2"])
    rows = [line.split() for line in capsys.readouterr().out.splitlines()[2:]]
    assert [row[0] for row in rows] == ["GW", "DPD-VV", "SC-VV", "S1", "S2", "Lowe", "PairOU", "OC"]
    assert all(float(row[3]) > 0 and float(row[4]) > 0 for row in rows)


@pytest.mark.parametrize("mode, name", [("rates", "GWW"), ("scale", "GWW"), ("thread-scaling", "GWW"),
                                        ("memory", "GWW"), ("shear", "GWW"), ("shear", "Langevin")])
def test_an_integrator_a_mode_cannot_run_is_refused_with_the_names_it_can(mode, name, capsys):
    with pytest.raises(SystemExit) as stopped:
        bench.main([mode, "--integrators", "GW", name])
    assert stopped.value.code == 2
    error = capsys.readouterr().err
    assert f"invalid choice: '{name}'" in error and "'GW'" in error


def test_sentinel_cost_is_measured(capsys):
    bench.main(["sentinel", "--sizes", "500", "--threads", "1", "--seconds", "0.02", "--repeats", "1", "--warmup", "2"])
    rows = capsys.readouterr().out.splitlines()[2:]
    assert len(rows) == 1 and rows[0].split()[:3] == ["GW", "500", "1"]


@pytest.mark.parametrize("mode, option", [("weight-exponent", ["--exponent", "1"]), ("exceptions", ["--chain-length", "10"]),
                                          ("transverse", ["--friction", "4.5"]), ("mdpd", [])])
def test_thermostat_option_costs_are_measured(mode, option, capsys):
    bench.main([mode, *option, "--integrators", "GW", "S1", "--sizes", "500", "--threads", "1", "--seconds", "0.02",
                "--repeats", "1", "--warmup", "2"])
    rows = [line.split() for line in capsys.readouterr().out.splitlines()[2:]]
    assert [row[:3] for row in rows] == [["GW", "500", "1"], ["S1", "500", "1"]]
    assert all(float(row[3]) > 0 and float(row[4]) > 0 for row in rows)


def test_charges_cost_is_measured_for_pme_alone_and_with_the_correction(capsys):
    bench.main(["charges", "--integrators", "GW", "--sizes", "500", "--threads", "1", "--seconds", "0.02",
                "--repeats", "1", "--warmup", "2"])
    lines = capsys.readouterr().out.splitlines()
    assert "PME's point charges" in lines[0] and "PME and the smearing correction" in lines[3]
    for row in (lines[2].split(), lines[5].split()):
        assert row[:3] == ["GW", "500", "1"] and float(row[3]) > 0 and float(row[4]) > 0


def test_scale_table_ratios_agree_with_its_rates(capsys):
    bench.main(["scale", "--integrators", "GW", "S1", "Langevin", "--sizes", "500", "1000",
                "--seconds", "0.02", "--repeats", "1", "--warmup", "2"])
    lines = capsys.readouterr().out.splitlines()
    assert lines[1].split() == ["N", "threads", "integrator", "steps/s", "Mparticle-steps/s",
                                "speed/GW", "cost/Langevin", "cost/particle"]
    rows = [line.split() for line in lines[2:]]
    assert [row[:3] for row in rows] == [[n, "1", name] for n in ("500", "1000") for name in ("GW", "S1", "Langevin")]
    rate = {(int(row[0]), row[2]): float(row[3]) for row in rows}
    for n, _, name, _, million, _, _, per_particle in rows:
        n = int(n)
        assert [float(million), float(per_particle)] == approx(
            [n * rate[n, name] / 1e6, 500 * rate[500, name] / (n * rate[n, name])], rel=0.01, abs=0.006)
    # GW and Langevin are timed together: each one's ratio to the other is the same median.
    for n in ("500", "1000"):
        gw, langevin = (next(row for row in rows if row[:3] == [n, "1", name]) for name in ("GW", "Langevin"))
        assert gw[6] == langevin[5] and float(gw[6]) > 0
    assert {row[5] for row in rows if row[2] == "GW"} == {"1.00"}
    assert {row[6] for row in rows if row[2] == "Langevin"} == {"1.00"}
    assert {row[7] for row in rows if row[0] == "500"} == {"1.00"}


def test_scale_ratios_are_medians_of_the_rounds_interleaved_with_each_integrator(capsys, monkeypatch):
    """Each integrator is timed in a group with GW and Langevin, and its ratios are the medians
    over that group's rounds of each round's ratio: here the references run at other speeds
    beside S1 than alone, and one round is slowed throughout (a busy spell of the machine).
    GW's and Langevin's own figures come from the rounds of both groups."""
    groups = []

    def fake_measure_group(n, labels, threads, args):
        groups.append(labels)
        if "S1" in labels:  # rounds' S1/GW: 0.5, 0.25, 0.4; Langevin/S1: 4, 8, 4.5 (ratios of the bests: 0.5, 4)
            return {"GW": [100.0, 10.0, 100.0], "Langevin": [200.0, 20.0, 180.0], "S1": [50.0, 2.5, 40.0]}
        return {"GW": [120.0, 100.0, 12.0], "Langevin": [150.0, 125.0, 15.0]}

    monkeypatch.setattr(bench_scale, "measure_group", fake_measure_group)
    bench.main(["scale", "--integrators", "S1", "GW", "Langevin", "--sizes", "500"])
    assert groups == [["GW", "Langevin"], ["GW", "Langevin", "S1"]]
    rows = {row[2]: row[3:] for row in (line.split() for line in capsys.readouterr().out.splitlines()[2:])}
    assert list(rows) == ["S1", "GW", "Langevin"]
    assert rows["S1"][0] == "50.00" and rows["S1"][2:4] == ["0.40", "4.50"]
    # GW and Langevin from all six rounds: Langevin/GW 1.25, 1.25, 1.25, 2, 2, 1.8; best 120 and 200.
    assert rows["GW"][0] == "120.00" and rows["GW"][2:4] == ["1.00", "1.52"]
    assert rows["Langevin"][0] == "200.00" and rows["Langevin"][2:4] == ["1.52", "1.00"]


def test_thread_scaling_prints_each_thread_count(capsys):
    bench.main(["thread-scaling", "--integrators", "GW", "S1", "--sizes", "500", "--threads", "1", "2",
                "--seconds", "0.02", "--repeats", "1", "--warmup", "2"])
    lines = capsys.readouterr().out.splitlines()
    assert lines[1].split() == ["N", "integrator", "threads", "steps/s", "speed-up"]
    rows = [line.split() for line in lines[2:6]]
    assert [row[:3] for row in rows] == [["500", name, threads] for name in ("GW", "S1") for threads in ("1", "2")]
    assert all(float(row[3]) > 0 for row in rows) and {row[4] for row in rows if row[2] == "1"} == {"1.00"}
    # Then two one-thread copies of each, in processes of their own, against one alone.
    assert lines[7].split() == ["N", "integrator", "copies", "speed-up"]
    copies = [line.split() for line in lines[8:]]
    assert [row[:3] for row in copies] == [["500", name, "2"] for name in ("GW", "S1")]
    assert all(0 < float(row[3]) < 10 for row in copies)


def test_copies_speedup_sums_the_copies_of_each_round():
    """Copy 0 alone at 100, 50, 90 steps/s; the two at once 80 + 90, 50 + 45, 85 + 90: ratios
    1.7, 1.9, 1.94, median 1.9."""
    rounds = {0: ([100.0, 50.0, 90.0], [80.0, 50.0, 85.0]), 1: ([], [90.0, 45.0, 90.0])}
    assert bench_copies.combine_copy_rounds(rounds, 2) == approx(1.9)


def test_copies_speedup_reports_a_copy_that_failed_or_stopped():
    assert bench_copies.combine_copy_rounds({0: ([1.0], [1.0]), 1: "failed: no memory"}, 2) == "failed: no memory"
    assert bench_copies.combine_copy_rounds({0: ([1.0], [1.0])}, 2) == "failed: a copy stopped"


def test_copies_speedup_reports_why_a_copy_stopped_before_the_broken_barrier():
    """The copies that found the barrier broken may report before the one that broke it."""
    rounds = {1: bench_copies.BROKEN_BARRIER, 0: "failed: MemoryError: "}
    assert bench_copies.combine_copy_rounds(rounds, 2) == "failed: MemoryError: "


def test_a_copy_that_stops_on_any_error_releases_the_others_and_says_why(monkeypatch):
    """Not only an OpenMM error: whatever stops a copy breaks the barrier, so that the others do
    not wait there COPY_TIMEOUT each, and is reported."""
    def no_scene(num_particles):
        raise ValueError("no scene")

    monkeypatch.setattr(bench_copies, "soft_scene", no_scene)
    barrier, results = threading.Barrier(2), queue.Queue()
    args = argparse.Namespace(edpd_alpha=20.0)
    bench_copies.copy_rounds(500, "GW", 0, barrier, results, args)
    assert barrier.broken
    assert results.get_nowait() == (0, "failed: ValueError: no scene")


def test_a_copy_that_finds_the_barrier_broken_says_so():
    barrier, results = threading.Barrier(2), queue.Queue()
    barrier.abort()
    args = argparse.Namespace(edpd_alpha=20.0, dt=0.05, platform="CPU", warmup=2, seconds=0.01, repeats=1)
    bench_copies.copy_rounds(500, "GW", 1, barrier, results, args)
    assert results.get_nowait() == (1, bench_copies.BROKEN_BARRIER)


@pytest.mark.parametrize("mode, module, measure, rows", [
    ("rates", bench_rates, "measure_sizes", []),
    ("scale", bench_scale, "measure_scale", [(500, 1, {"GW": (100.0, 1.0, 1.2)})]),
    ("thread-scaling", bench_threads, "measure_thread_scaling", [])])
def test_a_table_gives_the_catalogs_friction(mode, module, measure, rows, capsys, monkeypatch):
    monkeypatch.setattr(module, "FRICTION", 3.25)
    monkeypatch.setattr(module, measure, lambda *arguments: rows)
    bench.main([mode, "--integrators", "GW", "--threads", "1"])
    assert "gamma=3.25," in capsys.readouterr().out.splitlines()[0].replace(";", ",")


def test_thread_speedup_is_the_median_of_each_rounds_ratio(capsys, monkeypatch):
    """Round by round, not best against best: one thread's best round (100) and two threads'
    (170) would give 1.70; the rounds' ratios are 1.5, 1.9 and 1.89."""
    monkeypatch.setattr(bench_threads, "in_fresh_process", lambda function, *arguments: function(*arguments))
    monkeypatch.setattr(bench_threads, "thread_rates", lambda n, name, args: {1: [100.0, 50.0, 90.0], 2: [150.0, 95.0, 170.0]})
    monkeypatch.setattr(bench_copies, "copies_speedup", lambda n, name, copies, args: 1.95)
    bench.main(["thread-scaling", "--integrators", "S1"])
    rows = [line.split() for line in capsys.readouterr().out.splitlines()[2:4]]
    assert rows == [["256000", "S1", "1", "100.00", "1.00"], ["256000", "S1", "2", "170.00", "1.89"]]


def test_resident_bytes_sees_an_allocation():
    before = bench_memory.resident_bytes()
    block = np.ones(64 << 20, dtype=np.uint8)  # 64 MiB, every page touched
    assert bench_memory.resident_bytes() - before >= 60 << 20
    del block


def test_memory_table_counts_each_context_with_edpd_pairs(capsys):
    bench.main(["memory", "--integrators", "GW", "EDPD", "--sizes", "1000", "--memory-steps", "11"])
    lines = capsys.readouterr().out.splitlines()
    assert lines[1].split() == ["N", "integrator", "bytes/particle", "steps", "pair", "vars/particle"]
    (_, gw, gw_bytes, gw_steps, gw_pairs), (_, edpd, edpd_bytes, edpd_steps, edpd_pairs) = [
        line.split() for line in lines[2:]]
    assert (gw, edpd, gw_pairs) == ("GW", "EDPD", "-")
    assert float(gw_bytes) > 0 and int(gw_steps) <= 11 and int(edpd_steps) <= 11
    # Each EDPD pair variable is held in 24 bytes (PairMemory), so the reading holds at least that.
    assert float(edpd_pairs) > 1 and float(edpd_bytes) >= 24 * float(edpd_pairs)


def test_scale_table_on_opencl(capsys):
    """scale --platform OpenCL measures there (POCL here: the numbers say nothing about a GPU)."""
    import openmm
    names = {openmm.Platform.getPlatform(i).getName() for i in range(openmm.Platform.getNumPlatforms())}
    if "OpenCL" not in names:
        pytest.skip("OpenMM has no OpenCL platform here")
    bench.main(["scale", "--platform", "OpenCL", "--integrators", "GW", "Langevin", "--sizes", "500",
                "--seconds", "0.02", "--repeats", "1", "--warmup", "2"])
    lines = capsys.readouterr().out.splitlines()
    assert "OpenCL platform" in lines[0]
    rows = [line.split() for line in lines[2:]]
    assert [row[:3] for row in rows] == [["500", "1", "GW"], ["500", "1", "Langevin"]]
    assert all(float(row[3]) > 0 for row in rows)


def test_scale_groups_run_in_a_process_of_their_own():
    import os
    assert bench_timing.in_fresh_process(os.getpid) != os.getpid()
