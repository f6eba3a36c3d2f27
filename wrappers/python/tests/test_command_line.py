"""What `python3 -m openmmdpd.TOOL --help` tells a new user: what the tool does, roughly how long
a run with the defaults takes, and every option's default; a library module run as a command
says what to run instead.  The tools that draw do so with Agg, and importing the package's chart
helpers leaves an importer's backend (a notebook's) alone; log axes read as plain numbers."""
import argparse
import os
import subprocess
import sys

import pytest

import openmmdpd
from openmmdpd import bench, charts, compare, options, report, viscosity

PARSERS = {"compare": compare._parser, "viscosity": viscosity._parser, "bench": bench._parser,
           "report": report._parser}
# The bench's modes are subcommands, each with a --help of its own ("bench scale").
BENCH_MODES = next(action for action in bench._parser()._actions if isinstance(action, argparse._SubParsersAction))
PARSERS.update({f"bench {mode}": lambda mode=mode: BENCH_MODES.choices[mode] for mode in BENCH_MODES.choices})
LIBRARIES = {"viscosity_report": "openmmdpd.viscosity", "staggered": "openmmdpd.bench staggered",
             "shear": "openmmdpd.viscosity", "calibration": "openmmdpd.calibrate_den_otter_clarke"}


def run_module(module, *args):
    path = [os.path.dirname(os.path.dirname(openmmdpd.__file__))] + os.environ.get("PYTHONPATH", "").split(os.pathsep)
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(p for p in path if p), COLUMNS="100")
    return subprocess.run([sys.executable, "-m", f"openmmdpd.{module}", *args], env=env, capture_output=True,
                          text=True, timeout=120)


@pytest.mark.parametrize("name", list(PARSERS))
def test_help_gives_every_default_and_the_run_time(name):
    parser = PARSERS[name]()
    assert parser.prog == f"python3 -m openmmdpd.{name}"
    assert any(word in parser.description for word in ("minute", "seconds")), parser.description
    formatter = parser._get_formatter()
    for action in parser._actions:
        default = action.default
        if not action.option_strings or default in (None, False, argparse.SUPPRESS):
            continue
        assert action.help, f"{action.option_strings} has no help, so --help would not show its default"
        shown = formatter._get_help_string(action) % dict(vars(action), prog=parser.prog)
        assert "default" in shown, f"{action.option_strings}: {shown}"
    text = " ".join(parser.format_help().split())
    assert "show this help message and exit" in text


def test_defaults_are_shown_as_typed():
    parser = argparse.ArgumentParser(formatter_class=options.HelpFormatter)
    parser.add_argument("--dts", type=float, nargs="+", default=[0.02, 0.1], help="time steps")
    parser.add_argument("--share", type=float, default=0.5, help="a 50%% share")
    parser.add_argument("--integrators", nargs="+", help="all unless given")
    parser.add_argument("--quiet", action="store_true", help="no progress")
    text = " ".join(parser.format_help().split())
    assert "time steps (default: 0.02 0.1)" in text and "a 50% share (default: 0.5)" in text
    assert "all unless given --quiet" in text and "no progress" in text and "None" not in text


def test_compare_help_from_the_command_line():
    result = run_module("compare", "--help")
    assert result.returncode == 0, result.stderr
    text = " ".join(result.stdout.split())
    assert "about 10 minutes on 2 cores" in text and "(default: 0.02 0.03 0.04 0.06 0.1 0.15)" in text
    assert "--quick a run of seconds for CI: --particles 500" in text


@pytest.mark.parametrize("module", list(LIBRARIES))
def test_a_library_module_says_what_to_run_instead(module):
    result = run_module(module, "--help")
    assert result.returncode == 0, result.stderr
    assert "is a library module, not a command" in result.stdout
    assert LIBRARIES[module] in " ".join(result.stdout.split())
    result = run_module(module)
    assert result.returncode == 2 and "not a command" in result.stderr


def test_report_names_what_is_missing():
    result = run_module("report")
    assert result.returncode == 2 and "OUT.png, RESULTS.csv" in result.stderr


def test_importing_the_chart_helpers_keeps_the_backend_in_use():
    code = ("import matplotlib; matplotlib.use('svg'); import openmmdpd.charts, openmmdpd.report; "
            "print(matplotlib.get_backend())")
    path = [os.path.dirname(os.path.dirname(openmmdpd.__file__))] + os.environ.get("PYTHONPATH", "").split(os.pathsep)
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(p for p in path if p))
    result = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    assert result.stdout.strip() == "svg"


class Drawn(Exception):
    pass


@pytest.mark.parametrize("tool", [compare, report, viscosity])
def test_a_tool_that_draws_chooses_agg_first(tool, monkeypatch):
    """Before anything else, so that no chart is drawn with another backend."""
    def use_file_backend():
        raise Drawn

    monkeypatch.setattr(tool, "use_file_backend", use_file_backend)
    with pytest.raises(Drawn):
        tool.main([])


def test_use_file_backend_is_agg(monkeypatch):
    import matplotlib
    chosen = []
    monkeypatch.setattr(matplotlib, "use", chosen.append)
    charts.use_file_backend()
    assert [name.lower() for name in chosen] == ["agg"]


def test_log_axes_read_as_plain_numbers():
    """At the time steps of a sweep, and where matplotlib puts the ticks (its choice of which
    to label kept: here the decades and 2, 3, 4 and 6 between them)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    def labels(ticks=None, minor=False):
        fig = Figure()
        FigureCanvasAgg(fig)
        ax = fig.subplots()
        ax.plot([0.02, 0.15], [1, 2])
        charts.log_axis(ax, ticks=ticks)
        fig.canvas.draw()
        lo, hi = ax.get_xlim()
        return [label.get_text() for label in ax.get_xticklabels(minor=minor)
                if label.get_text() and lo <= label.get_position()[0] <= hi]

    assert labels([0.1, 0.02, 0.05, 0.02]) == ["0.02", "0.05", "0.1"]
    assert labels() == ["0.1"]
    assert labels(minor=True) == ["0.02", "0.03", "0.04", "0.06"]
