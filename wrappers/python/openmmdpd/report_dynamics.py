"""The dynamics part of a comparison run's report (see dynamics.py): charts of D, eta, Sc and the
transverse-current eta against dt and against cost, the dt -> 0 limits against independent runs,
and the recommended scheme and dt."""
import math
import os

import matplotlib.pyplot as plt

from . import dynamics
from .charts import figure_handles, integrator_style, legend_outside, log_axis, save

PANELS = (("D", "D, tracer diffusion (MSD)"), ("eta", "eta, NEMD shear viscosity"),
          ("Sc", "Sc = eta / (rho D)"), ("eta_T", "eta_T, transverse-current viscosity"))
RATIO_AXIS = (0.8, 1.25)  # the dt chart's y range: runs beyond it (Langevin) are marked at its edge


def _names(rows):
    return list(dict.fromkeys(row["integrator"] for row in rows))


def _stable(rows, name, key):
    return sorted((row for row in rows if row["integrator"] == name and row["status"] == "ok"
                   and math.isfinite(row.get(key, float("nan")))), key=lambda row: row["dt"])


def _edge_marks(ax, points, style):
    """Runs whose ratio lies beyond RATIO_AXIS, at the edge they pass, labelled with their value."""
    for dt, value in points:
        y = min(max(value, RATIO_AXIS[0]), RATIO_AXIS[1])
        ax.plot(dt, y, ls="none", marker=style["marker"], color=style["color"], mfc="white", clip_on=False)
        ax.annotate(f"{value:.3g}", (dt, y), xytext=(4, -8 if y == RATIO_AXIS[1] else 4), textcoords="offset points",
                    fontsize=6, color=style["color"])


def _own_error(row, key):
    """The run's own error of X / X0 (the limit's error is common to every run: drawn as a band)."""
    return row[key + "_err"] * row[key + "_rel"] / row[key]


def _limit_band(ax, rows, key):
    """1 ± the relative error of the DPD limit of key (dark), where a run has it."""
    for row in rows:
        if dynamics.limit_of(row["integrator"]) == dynamics.DPD_LIMIT and math.isfinite(row[key + "_rel"]):
            own = _own_error(row, key) / row[key + "_rel"]
            limit = math.sqrt(max(0.0, (row[key + "_rel_err"] / row[key + "_rel"]) ** 2 - own ** 2))
            ax.axhspan(1 - limit, 1 + limit, color="0.75", zorder=0, label="DPD's limit ± 1 standard error")
            return


def _vs_dt_chart(rows, path, scene):
    fig, axes = plt.subplots(2, 2, figsize=(11, 8), sharex=True)
    for ax, (key, label) in zip(axes.flat, PANELS):
        for name in _names(rows):
            style = integrator_style(name)
            ok = _stable(rows, name, key + "_rel")
            inside = [row for row in ok if RATIO_AXIS[0] <= row[key + "_rel"] <= RATIO_AXIS[1]]
            if inside:
                ax.errorbar([r["dt"] for r in inside], [r[key + "_rel"] for r in inside],
                            yerr=[_own_error(r, key) for r in inside], ms=5, capsize=2, label=name, **style)
            _edge_marks(ax, [(r["dt"], r[key + "_rel"]) for r in ok if r not in inside], style)
        ax.axhline(1, color="k", lw=0.8)
        ax.axhspan(1 - dynamics.USABLE_DYNAMICS, 1 + dynamics.USABLE_DYNAMICS, color="0.92", zorder=0, label="±5 %")
        _limit_band(ax, rows, key)
        ax.set_ylim(*RATIO_AXIS)
        ax.set_ylabel(f"{label.split(',')[0]} / its dt -> 0 limit")
        ax.set_title(label, fontsize=9)
        log_axis(ax, ticks=[row["dt"] for row in rows if row["status"] == "ok"])
    for ax in axes[-1]:
        ax.set_xlabel("dt")
    axes.flat[0].plot([], [], ls="none", marker="o", mfc="white", color="0.3",
                      label="beyond the axis (Langevin): at the edge, with its value")
    legend_outside(fig, *figure_handles(fig))
    fig.suptitle(f"Dynamics against time step, scene {scene}, ± each run's standard error: each over the dt -> 0 "
                 "limit of its model\n(Lowe and Lowe-mid: Lowe–Andersen's; the other integrators and Langevin: "
                 "DPD's)")
    save(fig, path)


def _pareto_chart(rows, path, scene):
    floor = 1e-3  # the log axis needs a positive value
    fig, axes = plt.subplots(2, 2, figsize=(11, 8))
    for ax, (key, label) in zip(axes.flat, PANELS):
        for name in _names(rows):
            style = integrator_style(name)
            ok = [r for r in _stable(rows, name, key + "_rel") if math.isfinite(r["cost_per_time"])]
            if not ok:
                continue
            y = [max(abs(r[key + "_rel"] - 1), floor) for r in ok]
            low = [min(r[key + "_rel_err"], yk - floor) for r, yk in zip(ok, y)]
            x = [r["cost_per_time"] for r in ok]
            ax.errorbar(x, y, xerr=[r["cost_per_time_err"] for r in ok], yerr=[low, [r[key + "_rel_err"] for r in ok]],
                        ms=5, capsize=2, lw=0.8, elinewidth=0.8, label=name, **style)
            for xk, yk, r in zip(x, y, ok):
                ax.annotate(f"{r['dt']:g}", (xk, yk), xytext=(3, 2), textcoords="offset points", fontsize=6,
                            color=style["color"])
        if ax.lines:
            log_axis(ax, "x")
            log_axis(ax, "y")
        else:
            ax.text(0.5, 0.5, "no run has it", transform=ax.transAxes, ha="center")
        ax.axhline(dynamics.USABLE_DYNAMICS, color="k", lw=0.8, ls="--")
        ax.set_ylabel(f"|X / X0 - 1|, X = {label.split(',')[0]}")
        ax.set_title(label, fontsize=9)
    for ax in axes[-1]:
        ax.set_xlabel("cost: Langevin steps per unit of simulated time")
    axes.flat[0].plot([], [], color="k", lw=0.8, ls="--", label="5 %")
    legend_outside(fig, *figure_handles(fig))
    fig.suptitle(f"Dynamics: accuracy against cost, scene {scene} (lower left is better; number: dt; floored at "
                 f"{floor:g})")
    save(fig, path)


CHARTS = [("dynamics_vs_dt.png", "Dynamics against time step", _vs_dt_chart),
          ("dynamics_vs_cost.png", "Dynamics: accuracy against cost", _pareto_chart)]


def draw(rows, out, scene):
    for filename, _, chart in CHARTS:
        chart(rows, os.path.join(out, filename), scene)


# --- text ------------------------------------------------------------------------------------------

def _pm(value, error, digits=4):
    if not math.isfinite(value):
        return ""
    return f"{value:.{digits}g} ± {error:.2g}" if math.isfinite(error) else f"{value:.{digits}g}"


def method(args):
    return ("Dynamics, in every stable run: D from the MSD (as above); eta from a second run of the same integrator "
            f"and dt from the state the first ended in, sheared (Lees–Edwards) at rate {args.nemd_rate:g} with the "
            f"imposed flow, equilibrated {args.equilibrate:g} and sampled {args.nemd_time:g} units of time, eta = "
            f"-<P_xy> / rate from the integrator's own pressure tensor in blocks of {dynamics.NEMD_BLOCK:g} (error "
            "from their statistical inefficiency); Sc = eta / (rho D); and eta_T from the equilibrium run itself: the transverse "
            "momentum current at the box's smallest wavevector k = 2 pi / L (k along x, y, z; both transverse "
            "components; real and imaginary parts: 12 series, sampled with <kT>) decays as exp(-nu k^2 t), nu = "
            "eta / rho, so eta_T = rho lambda / k^2 with lambda fitted to ln C(t) over its first e-fold (error: "
            "jackknife over the 12 series). A Langevin thermostat damps the current at its friction besides: its "
            "eta_T is rho (gamma / k^2 + nu), that of no fluid a DPD user models. "
            f"Each observable's reference X0 is its model's dt -> 0 limit: a weighted least-squares fit X = X0 + "
            f"b dt with one X0 and a slope per integrator, over the stable runs at dt <= {dynamics.LIMIT_DT:g} of "
            "every integrator with two or more there; its error from the fit, scaled by sqrt(chi^2/dof) where that "
            "exceeds 1. The DPD integrators share one limit; Lowe and Lowe-mid (Lowe–Andersen's collisions at the "
            "rate Gamma: the same equilibrium, other transport coefficients) have their own; Langevin is judged "
            "against DPD's. A run is usable if it is stable, its |<kT> - 1| is below "
            f"{dynamics.USABLE_KT:.0%} and its D and eta are within {dynamics.USABLE_DYNAMICS:.0%} of their limits "
            "(point values; a run without eta is not shown usable).")


# The model the independent runs are of: model B (scene soft at a = 25; the viscosity tool's model-b).
REFERENCE_MODEL = dict(scene="soft", a=25.0, viscosity_scene="model-b")


def _independent(args):
    """{key: (value, error, source)} of the independent runs args names, where their files exist
    and the run is of their model."""
    found = {}
    if args.scene != REFERENCE_MODEL["scene"] or getattr(args, "a", None) != REFERENCE_MODEL["a"]:
        return found
    path = getattr(args, "reference_diffusion", None)
    if path and os.path.exists(path):
        from .report import read_rows
        rows = [row for row in read_rows(path) if row["status"] == "ok" and math.isfinite(row["D"])
                and row["scene"] == REFERENCE_MODEL["scene"]]
        if rows:
            best = min(rows, key=lambda row: row["D_err"])
            found["D"] = (best["D"], best["D_err"], f"{best['integrator']} at dt {best['dt']:g}, "
                                                    f"{best['steps'] * best['dt']:g} time units (`{path}`)")
    path = getattr(args, "reference_viscosity", None)
    if path and os.path.exists(path):
        from .report import read_rows
        rows = [row for row in read_rows(path) if abs(row["rate"] - args.nemd_rate) < 1e-9
                and row["scene"] == REFERENCE_MODEL["viscosity_scene"]]
        if rows:
            row = rows[0]
            found["eta"] = (row["eta"], row["eta_err"],
                            f"viscosity tool, {row['integrator']} at dt {row['dt']:g}, {row['time']:g} time units at "
                            f"rate {row['rate']:g} (`{path}`)")
    return found


def limits_table(rows, args):
    fitted = dynamics.limits(rows)
    independent = _independent(args)
    lines = ["| model | X | X0 (dt -> 0) | runs | integrators | chi^2/dof | independent | difference / sigma |",
             "|---|---|---|---|---|---|---|---|"]
    for (limit, key), fit in fitted.items():
        if not fit:
            lines.append(f"| {limit} | {key} | too few runs |  |  |  |  |  |")
            continue
        other, z = "", ""
        if limit == dynamics.DPD_LIMIT and key in independent:
            value, error, source = independent[key]
            other = f"{_pm(value, error)}: {source}"
            z = f"{(fit['value'] - value) / math.hypot(fit['error'], error):+.1f}"
        lines.append(f"| {limit} | {key} | {_pm(fit['value'], fit['error'])} | {fit['runs']} | "
                     f"{', '.join(fit['integrators'])} | {fit['chi2_dof']:.2g} | {other} | {z} |")
    return lines


def transverse_check(rows):
    """eta_T against eta at each DPD integrator's smallest stable dt, in combined standard errors."""
    lines = []
    for name in _names(rows):
        ok = _stable(rows, name, "eta")
        if not ok or not math.isfinite(ok[0]["eta_T"]):
            continue
        row = ok[0]
        z = (row["eta_T"] - row["eta"]) / math.hypot(row["eta_T_err"], row["eta_err"])
        lines.append(f"{name} at dt {row['dt']:g}: eta_T {_pm(row['eta_T'], row['eta_T_err'])}, eta (NEMD) "
                     f"{_pm(row['eta'], row['eta_err'])}: {z:+.1f} sigma")
    return lines


def _runner_up(best, runner):
    """The next cheapest usable run, and whether the timings' errors tell the two apart (2 sigma)."""
    gap = (runner["cost_per_time"] - best["cost_per_time"]) / math.hypot(runner["cost_per_time_err"],
                                                                           best["cost_per_time_err"])
    tie = f", as cheap within the timings' errors ({gap:.1f} sigma apart): either will do" if gap < 2 else ""
    return (f" Next: {runner['integrator']} at dt {runner['dt']:g} ({runner['cost_per_time']:.3g} ± "
            f"{runner['cost_per_time_err']:.2g}){tie}.")


def recommendation(rows, scene):
    best = dynamics.recommend(rows)
    if best is None:
        return (f"No run on scene {scene} is usable (<kT> within {dynamics.USABLE_KT:.0%}, D and eta within "
                f"{dynamics.USABLE_DYNAMICS:.0%} of their limits).")
    others = sorted((row for row in rows if dynamics.usable(row) and row is not best),
                    key=lambda row: row["cost_per_time"])
    runner = _runner_up(best, others[0]) if others else ""
    return (f"Recommended on scene {scene}: **{best['integrator']} at dt {best['dt']:g}**, the cheapest usable run: "
            f"{best['cost_per_time']:.3g} ± {best['cost_per_time_err']:.2g} Langevin steps per unit of simulated "
            "time, "
            f"<kT> {_pm(best['kT'], best['kT_err'])}, D/D0 {_pm(best['D_rel'], best['D_rel_err'], 3)}, eta/eta0 "
            f"{_pm(best['eta_rel'], best['eta_rel_err'], 3)}. Usable runs: "
            f"{sum(1 for row in rows if dynamics.usable(row))} of {sum(row['status'] == 'ok' for row in rows)} "
            f"stable.{runner}")


def runs_table(rows):
    lines = ["| integrator | dt | D | D/D0 | eta | eta/eta0 | Sc | Sc/Sc0 | eta_T | eta_T/eta_T0 | usable |",
             "|---" * 11 + "|"]
    for row in rows:
        if row["status"] != "ok":
            continue
        cells = [_pm(row["D"], row["D_err"]), _pm(row["D_rel"], row["D_rel_err"], 3), _pm(row["eta"], row["eta_err"]),
                 _pm(row["eta_rel"], row["eta_rel_err"], 3), _pm(row["Sc"], row["Sc_err"]),
                 _pm(row["Sc_rel"], row["Sc_rel_err"], 3), _pm(row["eta_T"], row["eta_T_err"]),
                 _pm(row["eta_T_rel"], row["eta_T_rel_err"], 3), "yes" if dynamics.usable(row) else ""]
        lines.append(f"| {row['integrator']} | {row['dt']:g} | " + " | ".join(cells) + " |")
    return lines


def without_eta(rows):
    """The integrators with stable runs and no eta: no shear or no pressure tensor."""
    return [name for name in _names(rows) if any(row["integrator"] == name and row["status"] == "ok" for row in rows)
            and not _stable(rows, name, "eta")]


def section(rows, args):
    """The report's dynamics section (Markdown lines), charts included."""
    missing = without_eta(rows)
    lacking = (f"Without eta (no shear or no pressure tensor), so never usable: {', '.join(missing)}." if missing
               else "")
    lines = ["## Dynamics", "", method(args), "", lacking, "", recommendation(rows, args.scene), "",
             "### dt -> 0 limits", ""] + limits_table(rows, args) + [""]
    if not _independent(args):
        lines += ["No independent values of this model's limits are given (`--reference-diffusion`, "
                  "`--reference-viscosity`: runs of model B, scene soft at a = 25).", ""]
    check = transverse_check(rows)
    if check:
        lines += ["The transverse-current eta against NEMD's at each integrator's smallest stable dt:", ""]
        lines += [f"- {line}" for line in check] + [""]
    for filename, title, _ in CHARTS:
        lines += [f"### {title}", "", f"![{title}]({filename})", ""]
    return lines + ["### Dynamics of every stable run", ""] + runs_table(rows) + [""]
