"""Nikunen, Karttunen and Vattulainen (2003) reproduced: its kT-against-dt figures for
models A, B and the polymer (Figs. 1, 4, 7; with the configurational kT of model B, which the
paper did not measure), its Table VI (Nc in model B) and its Table VII (cost per step relative
to DPD-VV), ours next to the paper's, written to docs/results/paper000/.

    PYTHONPATH=build/python nice -n 10 /usr/bin/python3 examples/paper000.py [--quick] [--out DIR]
        [--scenes soft] [--integrators GW S1] [--dts 0.01 0.05]

Every run goes through the main job's run_one (openmmdpd.compare: the same observables, pymbar
standard errors and strict stability criteria), all of a scene's from one start equilibrated with
Langevin (compare.equilibrated_positions), each sampling the same simulated time; the costs are
one interleaved run of openmmdpd.bench_timing's measure.  Results go to runs-SCENE.csv, gr-soft.csv and
costs.csv; the charts and tables are drawn from those (--report-only: only that).  The tables in
README.md are replaced between its "generated" markers; the text around them is written by hand.
"""
import argparse
import csv
import math
import os
import sys
import time
from types import SimpleNamespace

import matplotlib.pyplot as plt
import numpy as np

from openmmdpd import bench_timing, catalog, compare, scenes
from openmmdpd.charts import figure_handles, integrator_style, legend_outside, log_axis, save

# The paper's integrators (GW at lambda 1/2 and 0.65 as the usual VV baselines, S2, and Lowe
# also at the paper's Gamma) and our middle scheme.
NAMES = ["GW", "GW0.65", "DPD-VV", "SC-VV", "S1", "S2", "Lowe", "Lowe-paper", "OC", "Lowe-mid"]
# Nikunen et al. 2003, §III.E: Lowe's Gamma chosen to match the DPD fluids' tracer diffusion.
PAPER_LOWE_GAMMA = {"ideal": 0.745, "soft": 0.44, "polymer": 0.745}
MODEL = {"ideal": "model A", "soft": "model B", "polymer": "the polymer"}
FIGURE = {"ideal": "Fig. 1", "soft": "Fig. 4", "polymer": "Fig. 7"}
DTS = {"ideal": [0.01, 0.02, 0.05, 0.1, 0.2, 0.3],
       "soft": [0.005, 0.01, 0.02, 0.05, 0.075, 0.1, 0.15],
       "polymer": [0.005, 0.01, 0.02, 0.025, 0.03, 0.04]}
PREPARE = 5.0           # time units of Langevin that equilibrate the one start of a scene's runs
EQUILIBRATION = 3.0     # time units each run equilibrates from that start before sampling
SAMPLE_TIME = {"ideal": 15.0, "soft": 15.0, "polymer": 20.0}
SAMPLE_INTERVAL = 0.1   # time units between kT samples
FRAME_INTERVAL = 0.75   # time units between g(r) and configurational-kT frames (model B only)

# Nikunen et al. 2003, Table VI: Nc in model B to the first minimum r1 of g(r), "error bars about +-0.05".
PAPER_TABLE_VI_DTS = [0.005, 0.01, 0.05, 0.075, 0.1]
PAPER_TABLE_VI = {"DPD-VV": [25.36, 25.37, 25.74, 26.72, 28.98], "SC-VV": [25.43, 25.54, 25.62, 26.78, 28.57],
                  "OC": [25.46, 25.51, 25.71, 26.69, 28.74], "S1": [25.53, 25.41, 25.73, 26.71, 28.44],
                  "Lowe": [25.35, 25.42, 25.59, 26.95, 29.12]}
# Nikunen et al. 2003, Table VII: CPU seconds per step, model B, N = 4000, dt = 0.05 (Alpha XP1000, 667 MHz).
PAPER_TABLE_VII = {"DPD-VV": (0.0363, 0.0005), "SC-VV": (0.1010, 0.0009), "OC": (0.0251, 0.0005),
                   "S1": (0.0256, 0.0005), "Lowe": (0.0143, 0.0005)}
PAPER_VERLET_LIST = (0.0293, 0.0003)
# What the paper's text says of each figure (it prints no numbers for them).
PAPER_SAYS = {
    "ideal": ["error of <kT> ~1e-4 (caption); y axis 0.88-1.00: every scheme that deviates runs cold",
              "DPD-VV and SC-VV reasonably good at small dt, major deviations at large dt; SC-VV the worst",
              "OC: <kT> decreases monotonically with dt up to 0.15, then rises rapidly; "
              "off by more than DPD-VV, less than SC-VV",
              "S1: within 0.5 % up to dt = 0.2", "Lowe: <kT> = 1 at every dt (Gamma 0.745)",
              "every scheme stable up to dt ~ 0.4 (§IV.D)"],
    "soft": ["error of <kT> ~1e-4 (caption); y axis up to 1.14",
             "all schemes very close to 1 at dt <= 0.01",
             "SC-VV: first decreases, pronounced minimum near dt = 0.05, then rises rapidly and turns unstable",
             "OC: relatively poor beyond dt = 0.025", "DPD-VV, S1, Lowe (Gamma 0.44): similar to each other"],
    "polymer": ["errors: whole system ~1e-4, chain 0.004 (caption)",
                "S1, Lowe, DPD-VV within 1 % up to dt ~ 0.02, unstable above",
                "OC: <kT> increases monotonically with dt, unlike the others",
                "chain kT (Fig. 7b) 'wholly consistent' with the whole system's (Fig. 7a)"],
}
COST_NAMES = ["DPD-VV", "SC-VV", "SC-VV6", "OC", "S1", "S2", "Lowe", "Lowe-paper", "GW", "GW0.65", "Lowe-mid",
              "Langevin"]


def factories(scene_name):
    """The catalog's integrators plus Lowe at the paper's Gamma and SC-VV with the paper's fixed
    six iterations (tolerance 0; ours stops when kT changes by less than 1e-6)."""
    made = catalog.integrators(scene_name)

    def lowe_paper(dt):
        integrator = made["Lowe"](dt)
        integrator.setDefaultFriction(PAPER_LOWE_GAMMA[scene_name])
        return integrator

    def sc_vv_six(dt):
        integrator = made["SC-VV"](dt)
        integrator.setTolerance(0.0)
        return integrator

    return dict(made, **{"Lowe-paper": lowe_paper, "SC-VV6": sc_vv_six})


def run_args(scene_name, args):
    """compare.run_one's settings for a scene's runs but gr_frames (see every_frame), times in
    reduced units (compare.schedule turns them into steps at each dt).  Frames on model B
    only: elsewhere one frame beyond the run, so none is taken but the MSD's origin.  run_one
    also times every run against Langevin; Table VII comes from bench instead, so that timing
    is kept as short as compare's --quick has it."""
    sample_time = SAMPLE_TIME[scene_name] * args.scale
    frame_every = FRAME_INTERVAL if scene_name == "soft" else 2 * sample_time
    return SimpleNamespace(platform="CPU", threads=args.threads, seed=args.seed,
                           instability_threshold=catalog.INSTABILITY_THRESHOLD, a=25.0,
                           prepare=PREPARE * args.scale, equilibrate=EQUILIBRATION * args.scale, time=sample_time,
                           sample_every=SAMPLE_INTERVAL, frame_every=frame_every,
                           cost_block=compare.QUICK["cost_block"], cost_repeats=compare.QUICK["cost_repeats"],
                           nemd_time=0.0)  # the paper measures no viscosity


def every_frame(dt, settings):
    """settings with gr_frames = every frame a run at dt takes (the MSD's origin and one every
    frame_every samples), so that g(r) averages all of them."""
    _, samples, frame_every = compare.schedule(dt, settings)
    return SimpleNamespace(**vars(settings), gr_frames=samples // frame_every + 1)


def run_scene(scene_name, args):
    """Every integrator at every dt of the scene, all from one Langevin-equilibrated start:
    (compare's rows, strictly judged; g(r)'s bin centres; {(name, dt): g(r)})."""
    scene = scenes.build_scene(scene_name, num_particles=args.particles)
    made = factories(scene_name)
    settings = run_args(scene_name, args)
    positions = compare.equilibrated_positions(scene, settings)
    rows, g_of = [], {}
    for name in args.integrators:
        for dt in args.dts or DTS[scene_name]:
            start = time.perf_counter()
            row, g = compare.run_one(scene, positions, name, made[name], dt, every_frame(dt, settings))
            rows.append(row)
            if g is not None:
                g_of[(name, dt)] = g
            print(f"{scene_name} {name} dt={dt:g}: {row['status']} {row['reason']} kT={row['kT']:.4f} "
                  f"({time.perf_counter() - start:.0f} s)", file=sys.stderr, flush=True)
    if scene_name == "soft":
        compare.judge_overlaps(rows)
    return rows, compare.g_r_centres(scene.system), g_of


def radius_for(r, g, nc, density=4.0):
    """The radius R at which our g(r) (bin centres r) gives Nc(R) = nc (Nc(R) grows monotonically)."""
    radii = np.linspace(0.9, 1.5, 601)
    return float(np.interp(nc, compare.coordination_at(np.asarray(r), np.array(g)[None, :], radii[:, None], density),
                           radii))


def measure_costs(args):
    """{name: seconds per step}: one interleaved bench run, model B, N particles, dt 0.05, best of repeats."""
    made = factories("soft")
    settings = SimpleNamespace(platform="CPU", dt=0.05, warmup=10, steps=None, seconds=args.cost_seconds,
                               repeats=args.repeats)
    rates = bench_timing.measure(scenes.soft_scene(num_particles=args.particles), [(n, made[n]) for n in COST_NAMES],
                                 args.threads, settings)
    return {name: (1 / rate if isinstance(rate, float) and rate > 0 else float("nan")) for name, rate in rates.items()}


# --- files ------------------------------------------------------------------------------------

def write_csv(path, rows, fields):
    with open(path, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=fields, extrasaction="ignore")
        writer.writeheader()
        writer.writerows(rows)


def read_csv(path):
    def value(text):
        try:
            return float(text)
        except ValueError:
            return text
    with open(path, newline="") as f:
        return [{k: value(v) for k, v in row.items()} for row in csv.DictReader(f)]


def write_gr(path, r, g_of):
    keys = sorted(g_of)
    with open(path, "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(["r"] + [f"{name} dt={dt:g}" for name, dt in keys])
        for k, rk in enumerate(r):
            writer.writerow([f"{rk:.4f}"] + [f"{g_of[key][k]:.5f}" for key in keys])


def read_gr(path):
    """(bin centres, {(name, dt): g(r)}) from write_gr's file; (None, {}) without one."""
    if not os.path.exists(path):
        return None, {}
    with open(path, newline="") as f:
        table = list(csv.reader(f))
    columns = list(zip(*[[float(x) for x in row] for row in table[1:]]))
    keys = [(head.split(" dt=")[0], float(head.split(" dt=")[1])) for head in table[0][1:]]
    return columns[0], dict(zip(keys, columns[1:]))


def _finite(x):
    return isinstance(x, float) and math.isfinite(x)


def _pm(row, key, digits=4):
    if not _finite(row.get(key)):
        return ""
    error = row.get(key + "_err")
    return f"{row[key]:.{digits}f} ± {error:.{digits}f}" if _finite(error) else f"{row[key]:.{digits}f}"


# --- charts -----------------------------------------------------------------------------------

def _style(name):
    """The package's style of each integrator; Lowe at the paper's Gamma, a name of this script
    alone, a lighter orange than Lowe's, dashed."""
    return dict(color="#fdb863", marker="H", ls="--") if name == "Lowe-paper" else integrator_style(name)


def _panel(ax, rows, key, title):
    """One observable against dt (log), error bars; runs the strict criteria call unstable hollow."""
    for name in NAMES:
        mine = sorted((r for r in rows if r["integrator"] == name and _finite(r.get(key))), key=lambda r: r["dt"])
        if not mine:
            continue
        style = _style(name)
        x, y = [r["dt"] for r in mine], [r[key] for r in mine]
        err = [r[key + "_err"] if _finite(r.get(key + "_err")) else 0 for r in mine]
        ax.errorbar(x, y, yerr=err, label=name, capsize=2, lw=1, ms=4, mfc="white", **style)
        ok = [(a, b) for a, b, r in zip(x, y, mine) if r["status"] == "ok"]
        if ok:
            ax.plot(*zip(*ok), ms=4, zorder=3, **dict(style, ls="none"))
    ax.axhline(1, color="k", lw=0.5)
    log_axis(ax, ticks=[r["dt"] for r in rows])
    ax.set_xlabel("dt")
    ax.set_title(title, fontsize=10)


def draw_scene(rows, scene_name, out):
    keys = {"ideal": [("kT", "kinetic <kT>")],
            "soft": [("kT", "kinetic <kT>"), ("kT_conf", "configurational kT (not in the paper)")],
            "polymer": [("kT", "kinetic <kT>, whole system (Fig. 7a)"), ("chain_kT", "kinetic <kT> of the chain (Fig. 7b)")]}
    fig, axes = plt.subplots(1, len(keys[scene_name]), figsize=(6 * len(keys[scene_name]), 4.5), squeeze=False)
    for ax, (key, title) in zip(axes[0], keys[scene_name]):
        _panel(ax, rows, key, title)
        values = [r[key] for r in rows if _finite(r.get(key))]
        if values:  # keep the view near 1 as the paper's axes do; far-off points are in the tables
            ax.set_ylim(max(min(values) - 0.01, 0.85), min(max(values) + 0.01, 1.25))
    legend_outside(fig, *figure_handles(fig))
    fig.suptitle(f"Nikunen et al. 2003, {FIGURE[scene_name]}: {MODEL[scene_name]} (scene {scene_name}); "
                 "hollow = unstable by the strict criteria", fontsize=10)
    save(fig, os.path.join(out, f"kT_vs_dt_{scene_name}.png"))


# --- tables -----------------------------------------------------------------------------------

def kt_table(rows, scene_name):
    keys = {"ideal": ["kT"], "soft": ["kT", "kT_conf"], "polymer": ["kT", "chain_kT"]}[scene_name]
    heads = {"kT": "kinetic <kT>", "kT_conf": "configurational kT", "chain_kT": "chain <kT>"}
    lines = [f"| integrator | dt | {' | '.join(heads[k] for k in keys)} | status |", "|---" * (3 + len(keys)) + "|"]
    for row in rows:
        status = f"unstable: {row['reason']}" if row["status"] == "unstable" else row["status"]
        if row["status"] != "ok" and row.get("note"):
            status += f" ({str(row['note'])[:70]})"
        lines.append(f"| {row['integrator']} | {row['dt']:g} | " + " | ".join(_pm(row, k) for k in keys)
                     + f" | {status} |")
    return lines


def table_vi(rows, r, g_of):
    """Nc ours at r = 1.16 and at our r1, the paper's (to its r1), at the paper's dts; and the radius
    at which our g(r) gives the paper's Nc (its r1, if the structures agree)."""
    lines = ["| integrator | dt | paper Nc (r1) | ours Nc(1.16) | ours - paper | ours Nc(r1) | our r1 | "
             "R where our Nc(R) = paper's |", "|---|---|---|---|---|---|---|---|"]
    for name in [*PAPER_TABLE_VI, "GW", "Lowe-paper", "Lowe-mid"]:
        for k, dt in enumerate(PAPER_TABLE_VI_DTS):
            row = next((r for r in rows if r["integrator"] == name and r["dt"] == dt), None)
            if row is None:
                continue
            paper = PAPER_TABLE_VI[name][k] if name in PAPER_TABLE_VI else None
            status = "" if row["status"] == "ok" else f" ({row['status']}: {row['reason']})"
            ours = row.get("Nc_1.16")
            diff = f"{ours - paper:+.2f}" if paper is not None and _finite(ours) else ""
            g = g_of.get((name, dt))
            radius = f"{radius_for(r, g, paper):.3f}" if paper is not None and g is not None else ""
            lines.append(f"| {name} | {dt:g} | {'' if paper is None else f'{paper:.2f} ± 0.05'} | "
                         f"{_pm(row, 'Nc_1.16', 2)}{status} | {diff} | {_pm(row, 'Nc', 2)} | {_pm(row, 'r1', 3)} | "
                         f"{radius} |")
    return lines


def table_vii(costs):
    """Ours against the paper's, per step and relative to DPD-VV; the paper's also with its Verlet-list
    update added to every step (its list was rebuilt every step but timed apart; ours is inside the step)."""
    ours_ref, (paper_ref, _), (verlet, verlet_err) = costs.get("DPD-VV"), PAPER_TABLE_VII["DPD-VV"], PAPER_VERLET_LIST
    lines = ["| integrator | paper s/step | paper / DPD-VV | paper + list / DPD-VV + list | ours ms/step | ours / DPD-VV |",
             "|---|---|---|---|---|---|"]
    for name in COST_NAMES:
        paper = PAPER_TABLE_VII.get(name)
        ours = costs.get(name, float("nan"))
        paper_text = (f"{paper[0]:.4f} ± {paper[1]:.4f} | {paper[0] / paper_ref:.2f} | "
                      f"{(paper[0] + verlet) / (paper_ref + verlet):.2f}" if paper else " | | ")
        lines.append(f"| {name} | {paper_text} | {1e3 * ours:.2f} | {ours / ours_ref:.2f} |")
    lines.append(f"| Verlet list update | {verlet:.4f} ± {verlet_err:.4f} | {verlet / paper_ref:.2f} | | "
                 "(inside every step) | |")
    return lines


def started_from(runs, args):
    """Where the runs started: compare's Langevin-equilibrated start, or, for CSVs written
    before compare timed every run against Langevin (no cost_ratio column), random positions."""
    if all("cost_ratio" in rows[0] for rows in runs.values() if rows):
        return (f"one start per scene equilibrated by {PREPARE * args.scale:g} time units of Langevin "
                f"(dt {compare.PREPARE_DT:g})")
    return "the scene's random positions (the script before compare's API change, commit e3462f6)"


def generated_tables(runs, gr, costs, args):
    lines = [f"Made by `examples/paper000.py`; N = {args.particles}, CPU platform, "
             f"{args.threads} thread(s), seed {args.seed}; per run {EQUILIBRATION * args.scale:g} time units of "
             f"equilibration from {started_from(runs, args)}, then "
             f"{SAMPLE_TIME['soft'] * args.scale:g} (models A, B) or "
             f"{SAMPLE_TIME['polymer'] * args.scale:g} (polymer) sampled, kT every {SAMPLE_INTERVAL:g}, "
             f"g(r) and configurational kT every {FRAME_INTERVAL:g} (model B). Errors: one standard error "
             "(pymbar's statistical inefficiency). Lowe-paper: Lowe at the paper's Gamma "
             f"({PAPER_LOWE_GAMMA['ideal']:g} in model A and the polymer, {PAPER_LOWE_GAMMA['soft']:g} in model B); "
             "Lowe and Lowe-mid: Gamma = 4.5, as everywhere in this project.", ""]
    if "soft" in runs:
        lines += ["### Table VI: coordination number Nc, model B", ""] + table_vi(runs["soft"], *gr) + [""]
    if costs:
        lines += [f"### Table VII: cost per step, model B, N = {args.particles}, dt = 0.05", "",
                  f"Ours: one interleaved run of `openmmdpd.bench_timing.measure`, best of {args.repeats} "
                  f"(~{args.cost_seconds:g} s each), {args.threads} thread(s); SC-VV6 is SC-VV with the "
                  "paper's fixed six iterations (tolerance 0).", ""] + table_vii(costs) + [""]
    for scene_name, rows in runs.items():
        lines += [f"### {FIGURE[scene_name]}: {MODEL[scene_name]}, kT against dt", "",
                  f"![{scene_name}](kT_vs_dt_{scene_name}.png)", "", "The paper's text on this figure:", ""]
        lines += [f"- {said}" for said in PAPER_SAYS[scene_name]] + [""] + kt_table(rows, scene_name) + [""]
    return lines


BEGIN, END = "<!-- generated by examples/paper000.py: begin -->", "<!-- generated by examples/paper000.py: end -->"


def write_readme(path, lines):
    """Replaces the text between the generated markers (the rest is hand-written), or starts the file."""
    text = open(path).read() if os.path.exists(path) else f"# Nikunen et al. (2003) reproduced\n\n{BEGIN}\n{END}\n"
    head, rest = text.split(BEGIN, 1)
    tail = rest.split(END, 1)[1]
    with open(path, "w") as f:
        f.write(head + BEGIN + "\n" + "\n".join(lines) + "\n" + END + tail)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", default=os.path.join("docs", "results", "paper000"))
    parser.add_argument("--scenes", nargs="+", default=["ideal", "soft", "polymer"], choices=list(DTS))
    parser.add_argument("--integrators", nargs="+", default=NAMES, choices=NAMES)
    parser.add_argument("--dts", type=float, nargs="+", help="default: each scene's in the paper's figures")
    parser.add_argument("--particles", type=int, default=4000)
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--seed", type=int, default=5)
    parser.add_argument("--repeats", type=int, default=5, help="interleaved cost measurements (best kept)")
    parser.add_argument("--cost-seconds", type=float, default=1.0, help="length of one cost measurement")
    parser.add_argument("--no-costs", action="store_true")
    parser.add_argument("--quick", action="store_true", help="a tenth of the sampling, for trying the script")
    parser.add_argument("--report-only", action="store_true", help="only redraw the report from the CSVs in --out")
    args = parser.parse_args(argv)
    args.scale = 0.1 if args.quick else 1.0
    os.makedirs(args.out, exist_ok=True)
    start = time.perf_counter()
    for scene_name in [] if args.report_only else args.scenes:
        rows, r, g_of = run_scene(scene_name, args)
        write_csv(os.path.join(args.out, f"runs-{scene_name}.csv"), rows, compare.COLUMNS)
        if g_of:
            write_gr(os.path.join(args.out, f"gr-{scene_name}.csv"), r, g_of)
    cost_path = os.path.join(args.out, "costs.csv")
    if not (args.no_costs or args.report_only):
        costs = measure_costs(args)
        write_csv(cost_path, [{"integrator": k, "s_per_step": v} for k, v in costs.items()], ["integrator", "s_per_step"])
    # The report: every scene with results in --out (a run of some scenes keeps the others').
    runs = {name: read_csv(os.path.join(args.out, f"runs-{name}.csv")) for name in DTS
            if os.path.exists(os.path.join(args.out, f"runs-{name}.csv"))}
    for scene_name, rows in runs.items():
        draw_scene(rows, scene_name, args.out)
    costs = ({row["integrator"]: row["s_per_step"] for row in read_csv(cost_path)}
             if os.path.exists(cost_path) else {})
    gr = read_gr(os.path.join(args.out, "gr-soft.csv"))
    write_readme(os.path.join(args.out, "README.md"), generated_tables(runs, gr, costs, args))
    print(f"done in {time.perf_counter() - start:.0f} s; {args.out}/README.md", file=sys.stderr)


if __name__ == "__main__":
    main()
