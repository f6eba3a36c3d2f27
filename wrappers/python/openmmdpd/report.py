"""Charts (PNG) and the Markdown report of a comparison run (see compare.py)."""
import csv
import math
import os

import matplotlib.pyplot as plt
import numpy as np

from . import dynamics, report_dynamics
from .charts import figure_handles, integrator_style, legend_outside, log_axis, save, use_file_backend
from .options import parser
from .protocol import (BOND_LIMIT, CHAIN_KT_TOLERANCE, CONF_KT_TOLERANCE, CORE_RADIUS, DIFFUSION_FIT,
                       DIFFUSION_GROUPS, OVERLAP_EXCESS, R1_BLOCKS, schedule)


def _ok(rows, name):
    return sorted((row for row in rows if row["integrator"] == name and row["status"] == "ok"),
                  key=lambda row: row["dt"])


def _unstable(rows, name):
    return sorted((row for row in rows if row["integrator"] == name and row["status"] == "unstable"),
                  key=lambda row: row["dt"])


def _names(rows):
    return list(dict.fromkeys(row["integrator"] for row in rows))


def first_unstable(rows, name):
    """(smallest unstable dt, its reason), or None."""
    unstable = _unstable(rows, name)
    return (unstable[0]["dt"], unstable[0]["reason"]) if unstable else None


def _mark_unstable(ax, points, color):
    """Unstable runs as crosses: at their value when it lies inside the axes drawn so far, on
    the top edge otherwise (blown-up runs have none, and far-off values would hide the rest)."""
    if not points:
        return
    bottom, top = ax.get_ylim()
    for x, y in points:
        inside = isinstance(y, float) and math.isfinite(y) and bottom <= y <= top
        ax.plot(x, y if inside else top, marker="x", ls="none", color=color, clip_on=False)
    if bottom > 0 or ax.get_yscale() != "log":
        ax.set_ylim(bottom, top)


def _mark_all_unstable(ax, rows, x_key, y_key):
    """Every integrator's unstable runs with an x value (_mark_unstable), in its colour, and one
    grey cross in the legend for them all."""
    marked = False
    for name in _names(rows):
        points = [(r[x_key], r[y_key]) for r in _unstable(rows, name) if math.isfinite(r[x_key])]
        _mark_unstable(ax, points, integrator_style(name)["color"])
        marked = marked or bool(points)
    if marked:
        ax.plot([], [], marker="x", ls="none", color="0.3", label="unstable (x; top edge: off the chart)")


def stability(rows, name):
    """(largest stable dt, largest stable dt with |<kT> - 1| < 1 %), None where there is none."""
    ok = _ok(rows, name)
    stable = max((row["dt"] for row in ok), default=None)
    accurate = max((row["dt"] for row in ok if row["kT_error"] < 0.01), default=None)
    return stable, accurate


SECOND_PANEL = {"soft": ("kT_conf", "configurational kT (soft repulsion)"), "polymer": ("chain_kT", "chain <kT>")}


def _kT_chart(rows, path, scene):
    panels = [("kT", "<kT> (kinetic, 3N-3 dof)")] + ([SECOND_PANEL[scene]] if scene in SECOND_PANEL else [])
    fig, axes = plt.subplots(1, len(panels), figsize=(5.5 * len(panels), 4.5), squeeze=False)
    for ax, (key, label) in zip(axes.flat, panels):
        for name in _names(rows):
            ok = [row for row in _ok(rows, name) if math.isfinite(row[key])]
            if ok:
                ax.errorbar([r["dt"] for r in ok], [r[key] for r in ok], yerr=[r[key + "_err"] for r in ok],
                            ms=5, capsize=2, label=name, **integrator_style(name))
        ax.axhline(1, color="k", lw=0.8)
        ax.axhspan(0.99, 1.01, color="0.9", zorder=0, label="±1 %")
        _mark_all_unstable(ax, rows, "dt", key)
        log_axis(ax, ticks=[row["dt"] for row in rows])
        ax.set_xlabel("dt (reduced units = ps)")
        ax.set_ylabel(label + ", ± 1 standard error")
    legend_outside(fig, *figure_handles(fig))
    fig.suptitle(f"Temperature against time step, scene {scene}")
    save(fig, path)


NOISE_FLOOR_SIGMAS = 3


def below_noise_floor(row):
    """True where |<kT> - 1| is under NOISE_FLOOR_SIGMAS standard errors: not resolved from 0."""
    return row["kT_error"] < NOISE_FLOOR_SIGMAS * row["kT_err"]


def _label_dt(ax, points, color):
    """Each point's dt in small print beside it: the Pareto chart's axes hold no dt."""
    for x, y, dt in points:
        ax.annotate(f"{dt:g}", (x, y), xytext=(3, 2), textcoords="offset points", fontsize=6, color=color)


def _pareto_chart(rows, path, scene):
    fig, ax = plt.subplots(figsize=(8, 5.5))
    floor = 1e-4  # the log axis needs a positive value
    for name in _names(rows):
        style = integrator_style(name)
        ok = [r for r in _ok(rows, name) if math.isfinite(r["cost_per_time"])]
        if not ok:
            continue
        x = [r["cost_per_time"] for r in ok]
        y = [max(r["kT_error"], floor) for r in ok]
        low = [min(r["kT_err"], yk - floor) for r, yk in zip(ok, y)]
        ax.errorbar(x, y, xerr=[r["cost_per_time_err"] for r in ok], yerr=[low, [r["kT_err"] for r in ok]], ms=5,
                    capsize=2, label=name, **style)
        hidden = [(xk, yk) for xk, yk, r in zip(x, y, ok) if below_noise_floor(r)]
        ax.plot([p[0] for p in hidden], [p[1] for p in hidden], ls="none", ms=7, mfc="white", **style)
        ax.plot(x, [NOISE_FLOOR_SIGMAS * r["kT_err"] for r in ok], ls="none", marker="_", ms=12, color=style["color"])
        _label_dt(ax, [(xk, yk, r["dt"]) for xk, yk, r in zip(x, y, ok)], style["color"])
    ax.plot([], [], ls="none", marker="_", ms=12, color="0.3", label=f"noise floor ({NOISE_FLOOR_SIGMAS} std. errors)")
    ax.plot([], [], ls="none", marker="o", ms=7, mfc="white", color="0.3", label="below its noise floor")
    ax.plot([], [], ls="none", marker="$0.02$", ms=14, color="0.3", label="beside a stable point: its dt")
    log_axis(ax, "x")
    log_axis(ax, "y")
    ax.axhline(0.01, color="k", lw=0.8, ls="--")
    _mark_all_unstable(ax, rows, "cost_per_time", "kT_error")
    ax.set_xlabel("cost: LangevinMiddleIntegrator steps per unit of simulated time\n"
                  "(step time / Langevin's, same System and dt, interleaved; divided by dt)")
    ax.set_ylabel(f"|<kT> - 1| ± 1 standard error (floored at {floor:g})")
    ax.set_title(f"Accuracy against cost, scene {scene} (lower left is better)")
    legend_outside(ax)
    save(fig, path)


def _gr_chart(rows, r, g_of, path, scene):
    names = [name for name in _names(rows) if _ok(rows, name)]
    cols = 3
    lines = max(1, math.ceil(len(names) / cols))
    fig, axes = plt.subplots(lines, cols, figsize=(10, 2.6 * lines), squeeze=False, sharex=True, sharey=True)
    for ax, name in zip(axes.flat, names):
        ok = _ok(rows, name)
        # the smallest dt as a thick grey reference, the largest over it in the integrator's colour
        colour = ("colour", dict(color=integrator_style(name)["color"], lw=1))
        shown = [(ok[0], ("grey", dict(color="0.8", lw=3))), (ok[-1], colour)] if len(ok) > 1 else [(ok[0], colour)]
        for row, (_, look) in shown:
            ax.plot(r, g_of[(name, row["dt"])], **look)
        ax.axhline(1, color="k", lw=0.6)
        # the dt of each line in the title: a legend would sit on the curves of so small a panel
        ax.set_title(f"{name}: dt " + ", ".join(f"{row['dt']:g} {word}" for row, (word, _) in shown), fontsize=9)
    for ax in axes.flat[len(names):]:
        ax.axis("off")
    fig.supxlabel("r (nm = rc)")
    fig.supylabel("g(r)")
    fig.suptitle(f"g(r) at the smallest (grey) and largest (colour) stable dt, scene {scene}")
    save(fig, path)


def _polymer_chart(rows, path, scene):
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.5))
    for name in _names(rows):
        style = integrator_style(name)
        ok = [row for row in _ok(rows, name) if math.isfinite(row["Rg"])]
        if ok:
            axes[0].errorbar([r["dt"] for r in ok], [r["Rg"] for r in ok], yerr=[r["Rg_err"] for r in ok], ms=5,
                             capsize=2, label=name, **style)
        done = [row for row in rows if row["integrator"] == name and math.isfinite(row["bond_max"])]
        if done:
            axes[1].plot([r["dt"] for r in done], [r["bond_max"] for r in done], ms=5, label=name, **style)
    for ax, label in ((axes[0], "chain Rg, ± 1 standard error"), (axes[1], "longest bond over the run")):
        if ax.lines:  # a log axis with nothing on it fails to draw
            log_axis(ax, ticks=[row["dt"] for row in rows])
        ax.set_xlabel("dt")
        ax.set_ylabel(label)
    axes[1].axhline(BOND_LIMIT, color="tab:red", lw=0.8, ls="--", label=f"limit {BOND_LIMIT:g}")
    legend_outside(fig, *figure_handles(fig))
    fig.suptitle(f"The chain against time step, scene {scene} (left: stable runs; right: every run that finished)")
    save(fig, path)


def _stability_chart(rows, path, scene):
    names = _names(rows)
    fig, ax = plt.subplots(figsize=(10, 0.45 * len(names) + 1.5))
    labelled = False
    for k, name in enumerate(names):
        stable, accurate = stability(rows, name)
        ax.barh(k + 0.2, stable or 0, height=0.4, color="tab:blue", label="largest stable dt" if k == 0 else None)
        ax.barh(k - 0.2, accurate or 0, height=0.4, color="tab:green",
                label="largest stable dt with |<kT>-1| < 1 %" if k == 0 else None)
        first = first_unstable(rows, name)
        if first:
            ax.plot(first[0], k, marker="x", color="tab:red", ls="none",
                    label=None if labelled else "smallest unstable dt: reason")
            ax.annotate(first[1], (first[0], k), xytext=(4, -3), textcoords="offset points", fontsize=7,
                        color="tab:red")
            labelled = True
    _mark_usable(ax, rows, names)
    ax.set_yticks(range(len(names)))
    ax.set_yticklabels(names)
    log_axis(ax, ticks=[row["dt"] for row in rows])
    ax.set_xlabel("dt (of those tried)")
    ax.set_title(f"Stability map, scene {scene}")
    legend_outside(ax, fontsize=8)
    save(fig, path)


def _mark_usable(ax, rows, names):
    """The usable region on the stability map: a diamond at every usable run, the recommended one ringed."""
    usable = [(row["dt"], names.index(row["integrator"])) for row in rows if dynamics.usable(row)]
    label = (f"usable: |<kT>-1| < {dynamics.USABLE_KT:.0%}, D and eta within {dynamics.USABLE_DYNAMICS:.0%} "
             "of their dt -> 0 limits")
    ax.plot([p[0] for p in usable], [p[1] for p in usable], ls="none", marker="D", ms=6, color="k", label=label)
    best = dynamics.recommend(rows)
    if best:
        ax.plot(best["dt"], names.index(best["integrator"]), ls="none", marker="o", ms=13, mfc="none", mew=1.5,
                color="tab:red", label="recommended: the cheapest usable run")


def _fmt(x, digits=4):
    if isinstance(x, str):
        return x
    return "" if x is None or (isinstance(x, float) and math.isnan(x)) else f"{x:.{digits}g}"


def _pm(row, key, digits=4):
    value, error = _fmt(row[key], digits), _fmt(row[key + "_err"], 2)
    return f"{value} ± {error}" if value and error else value


def _unstable_means(threshold):
    sentinel = (f", nor on a particle's kinetic energy above {threshold:g} kT (this plugin's integrators: the "
                f"instability sentinel, `sentinel`)" if threshold > 0 else " (the instability sentinel is off)")
    return ("A run is stable only if it passes every one of these, and unstable with the first it fails as its "
            "reason: it does not stop on a non-finite value, a particle jumping several cutoffs in one step or a "
            f"sampled kT above 10 (`blow-up`){sentinel}; its <kT> is within [0.5, 1.5] (`kT`); and on "
            f"scene soft its configurational kT is within {CONF_KT_TOLERANCE:.0%} of 1 (`kT_conf`) and it has no "
            f"overlapping particles (`overlap`): its g(r < {CORE_RADIUS:g}) — pairs that overlap by "
            f"{1 - CORE_RADIUS:.0%}, at {0.5 * 25 * (1 - CORE_RADIUS) ** 2:g} kT of repulsion (a = 25) — is not more "
            f"than {OVERLAP_EXCESS:g} above the median of the smallest dt's stable runs (about 0.02 in model B); on "
            f"scene polymer its chain <kT> is within {CHAIN_KT_TOLERANCE:.0%} of 1 (`chain_kT`) and no bond of the "
            f"chain is ever, at a sample, longer than {BOND_LIMIT:g} (`bond`; a harmonic bond of k = 7, rest length 0, "
            "has rms length 0.65 and passes 2.5 with probability 1.7e-9 per bond and sample).")


def _conventions():
    return ("Errors (±) are one standard error: of the mean of a time series from its statistical inefficiency "
            "(pymbar; the configurational kT as the ratio <sum |F|^2> / <sum lap U>, linearised), of r1 and "
            f"Nc(r1) from the spread over {R1_BLOCKS} blocks of frames, of D (the MSD's slope / 6 over the lags "
            f"{DIFFUSION_FIT[0]:g}–{DIFFUSION_FIT[1]:g}, or a quarter to half of a shorter run) from the spread of "
            f"the D of {DIFFUSION_GROUPS} interleaved sets of particles (D/D0 with the error of the dt -> 0 limit D0 "
            "too). On the Pareto chart a point whose "
            f"|<kT> - 1| is below {NOISE_FLOOR_SIGMAS} standard errors (its noise floor, a tick) is drawn hollow: "
            "it is not resolved from exact. Nc is given to the first minimum r1 and at the fixed radii 1.0 and 1.16: "
            "the minimum of a soft fluid's g(r) is so flat that r1 is poorly defined, and Nc grows there by "
            "dNc/dr = 4 pi rho r^2 g ~ 64 per unit r (model B), so r1's scatter swamps Nc(r1); at a fixed "
            "radius Nc differs between runs only by the structure.")


def _runs_table(rows):
    lines = ["| integrator | dt | status | <kT> | kT conf | g dev (ref) | g dev (1) | r1 | Nc(r1) | Nc(1.0) | "
             "Nc(1.16) | D/D0 | chain kT | Rg | longest bond | cost / Langevin step | CPU s / time |", "|---" * 17 + "|"]
    for row in rows:
        status = f"{row['status']} ({row['reason']})" if row["reason"] else row["status"]
        lines.append("| " + " | ".join([row["integrator"], _fmt(row["dt"]), status, _pm(row, "kT"), _pm(row, "kT_conf"),
                                        _fmt(row["g_dev_ref"], 2), _fmt(row["g_dev_ideal"], 2), _pm(row, "r1", 3),
                                        _pm(row, "Nc"), _pm(row, "Nc_1.0"), _pm(row, "Nc_1.16"),
                                        _pm(row, "D_rel", 3), _pm(row, "chain_kT"), _pm(row, "Rg"),
                                        _fmt(row["bond_max"], 3), _pm(row, "cost_ratio", 3),
                                        _fmt(row["cpu_s_per_time"], 3)]) + " |")
    return lines


def _setup(args, seconds):
    stride, samples, frame_every = schedule(min(args.dts), args)
    prepared = (f"the scene's random start after {args.prepare:g} units of time of LangevinMiddleIntegrator at dt "
                "0.005" if args.prepare > 0 else "the scene's random start")
    took = f" The whole run took {seconds:.0f} s (wall time)." if seconds is not None else ""
    return (f"N = {args.particles}, gamma (or Gamma) = 4.5, rc = 1, kT = 1, platform {args.platform} with "
            f"{args.threads} thread(s).{took} Every run starts from the same configuration, {prepared}; it "
            f"equilibrates for {args.equilibrate:g} units of time with its own integrator and dt, then samples "
            f"{args.time:g} units of time, whatever its dt: <kT> every {args.sample_every:g} (or every step), a frame "
            f"(positions for the MSD, configurational kT) every {args.frame_every:g}, g(r) on {args.gr_frames} frames "
            f"spread over the run (at the smallest dt: {samples * stride} steps, {samples} samples). Data: "
            "`results.csv`.")


def _cost_means(args, rows):
    own = [row["cost_ratio"] for row in rows if row["integrator"] == "Langevin" and math.isfinite(row["cost_ratio"])]
    errors = [row["cost_ratio_err"] / row["cost_ratio"] for row in rows if math.isfinite(row["cost_ratio_err"])]
    noise = (f" Langevin timed against itself reads {min(own):.3g}–{max(own):.3g}: the ratio's own noise."
             if own else "")
    spread = (f" Relative standard errors of the ratios: median {100 * sorted(errors)[len(errors) // 2]:.1f} %, "
              f"largest {100 * max(errors):.1f} %." if errors else "")
    return ("Cost is a ratio, measured in the same run: the time of one step of the integrator over that of one "
            "LangevinMiddleIntegrator step on the same System at the same dt, from the same state, in blocks of "
            f"the same number of steps of each (about {args.cost_block:g} CPU s of the integrator), alternated "
            f"{args.cost_repeats} times after a warm-up pair (CPU seconds); "
            "the median of the per-pair ratios, ± its standard error from their median absolute deviation. Machine "
            "noise slower than a pair of blocks cancels in each ratio, so the cost axis does not zigzag with the "
            "load. The Pareto chart's cost is that ratio divided by dt: LangevinMiddleIntegrator steps per unit of "
            "simulated time (Langevin at dt 0.01 costs 100). Raw seconds stay in `results.csv`: `cpu_s_per_time` and "
            "`wall_s_per_time` of the sampled steps, `langevin_cpu_s_per_time` of the timed Langevin blocks."
            + noise + spread)


def _precision(rows):
    errors = sorted((row["kT_err"], row["integrator"], row["dt"]) for row in rows
                    if row["status"] == "ok" and math.isfinite(row["kT_err"]))
    if not errors:
        return ""
    largest = errors[-1]
    return (f"Precision: the standard error of <kT> of the {len(errors)} stable runs is {errors[0][0]:.4f}–"
            f"{largest[0]:.4f} (median {errors[len(errors) // 2][0]:.4f}; largest: {largest[1]} at dt "
            f"{largest[2]:g}).")


# What a chart cannot show by itself, said under it in the report.
CAPTIONS = {"error_vs_cost.png": "The number beside each stable point is its dt.",
            "stability.png": "Diamonds: the usable runs (see Dynamics); the ringed one is recommended."}


def write_report(args, rows, r, g_of, seconds=None):
    out, scene = args.out, args.scene
    second = {"soft": " and configurational", "polymer": " and chain"}.get(scene, "")
    charts = [("kT_vs_dt.png", f"Kinetic{second} temperature against time step", _kT_chart),
              ("error_vs_cost.png", "Accuracy against cost (the Pareto chart)", _pareto_chart),
              ("stability.png", "Stability map", _stability_chart)]
    if scene == "polymer":
        charts.insert(1, ("polymer.png", "The chain: Rg and the longest bond", _polymer_chart))
    for filename, _, draw in charts:
        draw(rows, os.path.join(out, filename), scene)
    _gr_chart(rows, r, g_of, os.path.join(out, "gr.png"), scene)
    report_dynamics.draw(rows, out, scene)
    charts.insert(-1, ("gr.png", "Radial distribution functions", None))
    lines = [f"# Integrator comparison on scene `{scene}`", "", _setup(args, seconds), "", _precision(rows), "",
             _cost_means(args, rows), "", _unstable_means(args.instability_threshold), "", _conventions(), ""]
    lines += ["## Stability", "", "| integrator | largest stable dt | largest stable dt with \\|<kT>-1\\| < 1 % | "
              "smallest unstable dt: reason |", "|---|---|---|---|"]
    for name in _names(rows):
        first = first_unstable(rows, name)
        lines.append(f"| {name} | " + " | ".join(_fmt(x) for x in stability(rows, name))
                     + (f" | {first[0]:g}: {first[1]} |" if first else " | |"))
    lines.append("")
    for filename, title, _ in charts:
        lines += [f"## {title}", "", f"![{title}]({filename})", ""] + ([CAPTIONS[filename], ""] if filename in CAPTIONS
                                                                       else [])
    lines += report_dynamics.section(rows, args)
    lines += ["## All runs", ""] + _runs_table(rows)
    notes = [row for row in rows if row["note"]]
    if notes:
        lines += ["", "Notes (runs that are not stable, with the reason):", ""]
        lines += [f"- {row['integrator']} at dt {row['dt']:g}: {row['status']}: {row['note']}" for row in notes]
    with open(os.path.join(out, "report.md"), "w") as f:
        f.write("\n".join(lines) + "\n")


def _value(text):
    try:
        return float(text)
    except ValueError:
        return text


def read_rows(path):
    """The rows of a results.csv, numbers as floats."""
    with open(path) as f:
        return [{key: _value(value) for key, value in row.items()} for row in csv.DictReader(f)]


def read_gr(path):
    """(r, {(integrator, dt): g}) from a gr.csv, whose columns after r are named "NAME dt=DT"."""
    with open(path) as f:
        reader = csv.reader(f)
        header = next(reader)
        table = np.array([[float(x) for x in line] for line in reader]).reshape(-1, len(header))
    g_of = {}
    for k, column in enumerate(header[1:], 1):
        name, dt = column.rsplit(" dt=", 1)
        g_of[(name, float(dt))] = table[:, k]
    return table[:, 0], g_of


def stability_map(tables, path):
    """One stability map for several scenes: per integrator, a bar per scene to its largest
    stable dt, a cross at its smallest unstable dt labelled with the reason, and a
    diamond at each usable run (dynamics.usable).
    tables: {scene: rows}."""
    names = list(dict.fromkeys(name for rows in tables.values() for name in _names(rows)))
    height = 0.8 / len(tables)
    fig, ax = plt.subplots(figsize=(8, 0.6 * len(names) * len(tables) / 2 + 1.5))
    any_usable = False
    for s, (scene, rows) in enumerate(tables.items()):
        offset = 0.4 - height * (s + 0.5)
        for k, name in enumerate(names):
            stable = stability(rows, name)[0]
            ax.barh(k + offset, stable or 0, height=height * 0.9, color=f"C{s}", label=scene if k == 0 else None)
            usable = [row["dt"] for row in rows if row["integrator"] == name and row.get("usable") == 1]
            ax.plot(usable, [k + offset] * len(usable), ls="none", marker="D", ms=4, color="k",
                    label="usable (kT 1 %, D and eta 5 %)" if usable and not any_usable else None)
            any_usable = any_usable or bool(usable)
            first = first_unstable(rows, name)
            if first:
                ax.plot(first[0], k + offset, marker="x", color=f"C{s}", ls="none")
                ax.annotate(first[1], (first[0], k + offset), xytext=(4, -3), textcoords="offset points",
                            fontsize=6, color=f"C{s}")
    ax.set_yticks(range(len(names)))
    ax.set_yticklabels(names)
    ax.invert_yaxis()
    log_axis(ax, ticks=[row["dt"] for rows in tables.values() for row in rows])
    ax.set_xlabel("dt: bar to the largest stable dt; x at the smallest unstable dt, with the reason; "
                  "diamond: a usable run")
    ax.set_title("Stability map: " + ", ".join(tables))
    legend_outside(ax, fontsize=8)
    save(fig, path)


def _parser():
    result = parser("report", "One stability map (PNG) of several comparison runs: per integrator, a bar per "
                    "scene to its largest stable dt and a cross at its smallest unstable dt with the reason, "
                    "from the results.csv that `python3 -m openmmdpd.compare` wrote. (One run's own charts and "
                    "report are redrawn by `python3 -m openmmdpd.compare --redraw --out FOLDER`.)",
                    "It only reads the CSV files and draws: a few seconds.")
    result.add_argument("out", metavar="OUT.png", help="the chart to write")
    result.add_argument("results", metavar="RESULTS.csv", nargs="+", help="results.csv of each run (one per scene)")
    return result


def main(argv=None):
    """python3 -m openmmdpd.report OUT.png RESULTS.csv...: one stability map of several runs."""
    use_file_backend()
    args = _parser().parse_args(argv)
    tables = {}
    for path in args.results:
        rows = read_rows(path)
        tables[rows[0]["scene"]] = rows
    stability_map(tables, args.out)


if __name__ == "__main__":
    main()
