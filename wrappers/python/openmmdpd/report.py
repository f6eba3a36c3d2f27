"""Charts (PNG) and the Markdown report of a comparison run (see compare.py)."""
import math
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def _ok(rows, name):
    return sorted((row for row in rows if row["integrator"] == name and row["status"] == "ok"),
                  key=lambda row: row["dt"])


def _names(rows):
    return list(dict.fromkeys(row["integrator"] for row in rows))


def stability(rows, name):
    """(largest stable dt, largest dt with |<kT> - 1| < 1 %, largest dt with the
    configurational kT within 10 % of 1), None where there is none."""
    ok = _ok(rows, name)
    stable = max((row["dt"] for row in ok), default=None)
    accurate = max((row["dt"] for row in ok if row["kT_error"] < 0.01), default=None)
    structure = max((row["dt"] for row in ok if abs(row["kT_conf"] - 1) <= 0.1), default=None)
    return stable, accurate, structure


def _kT_chart(rows, path, scene):
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for name in _names(rows):
        ok = _ok(rows, name)
        if ok:
            ax.errorbar([r["dt"] for r in ok], [r["kT"] for r in ok], yerr=[r["kT_err"] for r in ok],
                        marker="o", capsize=2, label=name)
    ax.axhline(1, color="k", lw=0.8)
    ax.axhspan(0.99, 1.01, color="0.9", zorder=0, label="±1 %")
    ax.set_xscale("log")
    ax.set_xlabel("dt (reduced units = ps)")
    ax.set_ylabel("<kT> (kinetic, 3N-3 dof)")
    ax.set_title(f"Temperature against time step, scene {scene}")
    ax.legend(fontsize=7, ncol=2)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _pareto_chart(rows, path, scene):
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for name in _names(rows):
        ok = _ok(rows, name)
        if ok:
            ax.plot([r["cpu_s_per_time"] for r in ok], [max(r["kT_error"], 1e-4) for r in ok], marker="o", label=name)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.axhline(0.01, color="k", lw=0.8, ls="--")
    ax.set_xlabel("cost: CPU seconds per unit of simulated time")
    ax.set_ylabel("|<kT> - 1| (floored at 1e-4)")
    ax.set_title(f"Accuracy against cost, scene {scene} (lower left is better)")
    ax.legend(fontsize=7, ncol=2)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _gr_chart(rows, r, g_of, path, scene):
    names = [name for name in _names(rows) if _ok(rows, name)]
    cols = 3
    lines = max(1, math.ceil(len(names) / cols))
    fig, axes = plt.subplots(lines, cols, figsize=(10, 2.6 * lines), squeeze=False, sharex=True, sharey=True)
    for ax, name in zip(axes.flat, names):
        ok = _ok(rows, name)
        for row in (ok[0], ok[-1]) if len(ok) > 1 else ok:
            ax.plot(r, g_of[(name, row["dt"])], label=f"dt {row['dt']:g}")
        ax.axhline(1, color="k", lw=0.6)
        ax.set_title(name, fontsize=9)
        ax.legend(fontsize=7)
    for ax in axes.flat[len(names):]:
        ax.axis("off")
    fig.supxlabel("r (nm = rc)")
    fig.supylabel("g(r)")
    fig.suptitle(f"g(r) at the smallest and largest stable dt, scene {scene}")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _legend(ax, **kwargs):
    if ax.get_legend_handles_labels()[0]:
        ax.legend(**kwargs)


def _diffusion_chart(rows, path, scene):
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for name in _names(rows):
        ok = [row for row in _ok(rows, name) if math.isfinite(row["D_ratio"])]
        if ok:
            ax.plot([r["dt"] for r in ok], [r["D_ratio"] for r in ok], marker="o", label=name)
    ax.axhline(1, color="k", lw=0.8)
    ax.set_xscale("log")
    ax.set_xlabel("dt")
    ax.set_ylabel("D(dt) / D(smallest dt)")
    ax.set_title(f"Tracer diffusion against time step, scene {scene}")
    _legend(ax, fontsize=7, ncol=2)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _stability_chart(rows, path, scene):
    names = _names(rows)
    fig, ax = plt.subplots(figsize=(7, 0.45 * len(names) + 1.5))
    for k, name in enumerate(names):
        stable, accurate, structure = stability(rows, name)
        ax.barh(k + 0.27, stable or 0, height=0.27, color="tab:blue", label="largest stable dt" if k == 0 else None)
        ax.barh(k, accurate or 0, height=0.27, color="tab:green", label="largest dt with |<kT>-1| < 1 %" if k == 0 else None)
        ax.barh(k - 0.27, structure or 0, height=0.27, color="tab:orange",
                label="largest dt with |kT_conf-1| < 10 %" if k == 0 else None)
    ax.set_yticks(range(len(names)))
    ax.set_yticklabels(names)
    ax.set_xlabel("dt (of those tried)")
    ax.set_title(f"Stability map, scene {scene}")
    ax.legend(fontsize=8, loc="lower right")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _fmt(x, digits=4):
    if isinstance(x, str):
        return x
    return "" if x is None or (isinstance(x, float) and math.isnan(x)) else f"{x:.{digits}g}"


def _unstable_means(threshold):
    sentinel = (f", or a particle's kinetic energy above {threshold:g} kT (this plugin's integrators: the "
                f"instability sentinel)" if threshold > 0 else " (the instability sentinel is off)")
    return (f"A run is unstable if it stops on a non-finite value, a particle jumping several cutoffs in one step, "
            f"a sampled kT above 10{sentinel}; or if its <kT> is outside [0.5, 1.5].")


def write_report(args, rows, r, g_of):
    out, scene = args.out, args.scene
    charts = [("kT_vs_dt.png", "Kinetic temperature against time step", _kT_chart),
              ("error_vs_cost.png", "Accuracy against cost (the Pareto chart)", _pareto_chart),
              ("diffusion.png", "Tracer diffusion relative to the smallest dt", _diffusion_chart),
              ("stability.png", "Stability map", _stability_chart)]
    for filename, _, draw in charts:
        draw(rows, os.path.join(out, filename), scene)
    _gr_chart(rows, r, g_of, os.path.join(out, "gr.png"), scene)
    charts.insert(2, ("gr.png", "Radial distribution functions", None))
    lines = [f"# Integrator comparison on scene `{scene}`", "",
             f"N = {args.particles}, {args.steps} sampled steps after {args.equilibrate} of equilibration, "
             f"gamma (or Gamma) = 4.5, rc = 1, kT = 1, platform {args.platform} with {args.threads} thread(s). "
             "Costs are CPU seconds of the integration steps alone, per unit of simulated time, "
             "measured in this run. Data: `results.csv`. " + _unstable_means(args.instability_threshold), ""]
    lines += ["## Stability", "",
              "| integrator | largest stable dt | largest dt with \\|<kT>-1\\| < 1 % | largest dt with \\|kT_conf-1\\| < 10 % |",
              "|---|---|---|---|"]
    for name in _names(rows):
        stable, accurate, structure = stability(rows, name)
        lines.append(f"| {name} | {_fmt(stable)} | {_fmt(accurate)} | {_fmt(structure)} |")
    lines.append("")
    for filename, title, _ in charts:
        lines += [f"## {title}", "", f"![{title}]({filename})", ""]
    lines += ["## All runs", "",
              "| integrator | dt | status | <kT> | ± | kT conf | g dev (ref) | g dev (1) | Nc | D/D0 | chain kT | Rg | CPU s / time |",
              "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for row in rows:
        lines.append("| " + " | ".join([row["integrator"], _fmt(row["dt"]), row["status"], _fmt(row["kT"]), _fmt(row["kT_err"], 2),
                                        _fmt(row["kT_conf"]), _fmt(row["g_dev_ref"], 2), _fmt(row["g_dev_ideal"], 2),
                                        _fmt(row["Nc"]), _fmt(row["D_ratio"], 3), _fmt(row["chain_kT"]), _fmt(row["Rg"]),
                                        _fmt(row["cpu_s_per_time"], 3)]) + " |")
    notes = [row for row in rows if row["note"]]
    if notes:
        lines += ["", "Notes (runs that did not complete, or whose configurations were off):", ""]
        lines += [f"- {row['integrator']} at dt {row['dt']:g}: {row['status']}: {row['note']}" for row in notes]
    with open(os.path.join(out, "report.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
