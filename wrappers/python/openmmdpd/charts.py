"""The look every chart of the tools shares: one colour and marker per integrator, legends
outside the axes, plain numbers on log axes.

Importing it leaves matplotlib's backend alone (a notebook keeps its own); the command-line
tools that draw call use_file_backend first."""
import matplotlib
from matplotlib.figure import Figure
import matplotlib.pyplot as plt
from matplotlib.ticker import LogFormatter, NullFormatter

# Each name of openmmdpd.catalog, and its colour and marker: the same on every chart, and no two
# alike, so a point is told by its colour or by its marker alone (in grey print too).  Related
# schemes share a hue family (Lowe orange, Lowe-mid red); grey is kept for references and "x"
# for unstable runs.
INTEGRATOR_STYLES = {
    "Langevin": dict(color="black", marker="*"),
    "GW": dict(color="tab:blue", marker="o"),
    "GW0.65": dict(color="tab:cyan", marker="s"),
    "DPD-VV": dict(color="tab:green", marker="^"),
    "SC-VV": dict(color="tab:olive", marker="v"),
    "S1": dict(color="tab:purple", marker="D"),
    "S2": dict(color="tab:pink", marker="d"),
    "Lowe": dict(color="tab:orange", marker="P"),
    "Lowe-mid": dict(color="tab:red", marker="p"),
    "PairOU": dict(color="tab:brown", marker="<"),
    "PairOU-mid": dict(color="darkgoldenrod", marker=">"),
    "OC": dict(color="teal", marker="h"),
    "OpenMM-DPD": dict(color="navy", marker="8"),
}


def use_file_backend():
    """Makes pyplot draw with Agg: the tools only write PNG files, and Agg needs no display
    (a headless machine, CI), whatever backend the user's setup would otherwise pick."""
    matplotlib.use("Agg")


def integrator_style(name):
    """The colour and marker of the integrator called `name` (a copy: callers may add to it)."""
    return dict(INTEGRATOR_STYLES[name])


class PlainLogFormatter(LogFormatter):
    """Tick labels of a log axis as plain numbers (0.02, 0.1, 300), not 2×10⁻²; matplotlib's own
    choice of which ticks to label is kept: a tick LogFormatter leaves blank stays blank.  Only
    its public call is used, so the labels do not hang on how matplotlib formats numbers inside."""

    def __call__(self, x, pos=None):
        return self.fix_minus(f"{x:g}") if super().__call__(x, pos) else ""


def log_axis(ax, which="x", ticks=None):
    """Makes the x (or y) axis of ax logarithmic, with plain tick labels: at `ticks` alone where
    given (the time steps a sweep measured), else where matplotlib puts them."""
    (ax.set_xscale if which == "x" else ax.set_yscale)("log")
    axis = ax.xaxis if which == "x" else ax.yaxis
    if ticks is not None:
        axis.set_ticks(sorted(set(ticks)), [f"{x:g}" for x in sorted(set(ticks))])
        axis.set_minor_formatter(NullFormatter())
        return
    axis.set_major_formatter(PlainLogFormatter())
    # some ticks between the decades labelled (2, 5) up to 2 decades, where a decade alone says little
    axis.set_minor_formatter(PlainLogFormatter(labelOnlyBase=False, minor_thresholds=(2, 0.5)))


def legend_outside(target, handles=None, labels=None, **kwargs):
    """A legend right of the axes (or of a figure's panels), so that it covers no data; `save`
    widens the image to hold it.  Nothing when there is nothing to label."""
    if handles is None:
        handles, labels = target.get_legend_handles_labels()
    if not handles:
        return
    kwargs.setdefault("fontsize", 7)
    if isinstance(target, Figure):
        target.legend(handles, labels, loc="center left", bbox_to_anchor=(1.0, 0.5), **kwargs)
    else:
        target.legend(handles, labels, loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0, **kwargs)


def figure_handles(fig):
    """(handles, labels) of every panel of fig, each label once: the input of one figure legend."""
    seen = {}
    for ax in fig.axes:
        for handle, label in zip(*ax.get_legend_handles_labels()):
            seen.setdefault(label, handle)
    return list(seen.values()), list(seen)


def save(fig, path, dpi=110):
    """Writes fig as a PNG cropped to what it holds, legends outside the axes included, and closes it."""
    fig.tight_layout()
    fig.savefig(path, dpi=dpi, bbox_inches="tight")
    plt.close(fig)
