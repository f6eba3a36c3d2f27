"""Charts (PNG) and the Markdown report of a viscosity run (see viscosity.py)."""
import math
import os
import time

import matplotlib.pyplot as plt
import numpy as np

from .analysis import jackknife_error
from .catalog import FRICTION
from .charts import figure_handles, integrator_style, legend_outside, save
from .options import not_a_command
from .viscosity_fluids import SCENES, groot_warren_estimate

AGREEMENT_SIGMAS = 3  # NEMD at the lowest rate and Green–Kubo agree within this many combined standard errors
TARGET_KT = 1.0  # the thermostat's kT, reduced units
# A sheared run's peculiar kT further than this from TARGET_KT is flagged as off, as compare's
# configurational and chain kT are: viscous heating at the rates used here raises it by a few
# per cent (1.025-1.034 at rate 0.5 in the committed long runs), an unequilibrated start or an
# integrator near its stability limit by more.
KT_TOLERANCE = 0.10
KT_SIGMAS = 3  # ... and one whose 3 standard errors exceed the tolerance as too noisy to check


def _scenes(nemd, gk):
    return list(dict.fromkeys([row["scene"] for row in nemd] + list(gk)))


def _rows(nemd, scene):
    return sorted((row for row in nemd if row["scene"] == scene), key=lambda row: row["rate"])


def _panels(count):
    fig, axes = plt.subplots(1, count, figsize=(5.5 * count, 4.3), squeeze=False)
    return fig, axes.flat


def viscosity_chart(path, nemd, gk):
    """eta against the rate (NEMD), the Green–Kubo value as a band, Groot–Warren's estimate dashed."""
    scenes = _scenes(nemd, gk)
    fig, axes = _panels(len(scenes))
    for ax, scene in zip(axes, scenes):
        rows = _rows(nemd, scene)
        if rows:
            ax.errorbar([r["rate"] for r in rows], [r["eta"] for r in rows], yerr=[r["eta_err"] for r in rows],
                        capsize=3, label=f"NEMD -<P_xy>/rate ({rows[0]['integrator']})",
                        **integrator_style(rows[0]["integrator"]))
        if scene in gk:
            total = gk[scene]["total"]
            ax.axhspan(total["eta"] - total["eta_err"], total["eta"] + total["eta_err"], color="0.75", alpha=0.6,
                       label="Green–Kubo ± 1 sigma (statistical and systematic)")
        ax.axhline(groot_warren_estimate(SCENES[scene]["density"]), color="k", ls="--", lw=1,
                   label="Groot–Warren estimate")
        ax.set_xlim(left=0)
        ax.set_xlabel("shear rate (1/ps)")
        ax.set_ylabel("eta (kT ps / nm^3, reduced), ± 1 standard error")
        ax.set_title(f"{scene}: Green–Kubo {gk[scene]['total']['eta']:.3f} ± {gk[scene]['total']['eta_err']:.3f}"
                     if scene in gk else scene)
    legend_outside(fig, *figure_handles(fig), fontsize=8)
    save(fig, path)


def green_kubo_chart(path, gk):
    """The running Green–Kubo integral against the lag, with and without the thermostat part; the
    tail fit's value with its error (stat and systematic) as a band, its starts' and ends' ranges shaded."""
    fig, axes = _panels(len(gk))
    for ax, (scene, results) in zip(axes, gk.items()):
        total = results["total"]
        ax.axvspan(total["fit_start_from"], total["fit_start_to"], color="0.85", label="tail fit starts")
        ax.axvspan(total["fit_end_from"], total["fit_end_to"], color="0.93", label="tail fit ends")
        for k, name in enumerate(("total", "total - thermostat")):
            r = results[name]
            ax.plot(r["lags"], r["running"], color=f"C{k}", lw=1, label=f"{name}: running integral")
            ax.axhspan(r["eta"] - r["eta_err"], r["eta"] + r["eta_err"], color=f"C{k}", alpha=0.25,
                       label=f"{name}: tail fit ± 1 sigma")
        ax.set_xlabel("lag (ps)")
        ax.set_ylabel("V/kT Delta [C(0)/2 + sum C(k)]")
        ax.set_title(f"{scene}, Green–Kubo")
    legend_outside(fig, *figure_handles(fig), fontsize=8)
    save(fig, path)


def temperature_chart(path, nemd):
    """Peculiar kT and its components against the rate."""
    scenes = _scenes(nemd, {})
    fig, axes = _panels(len(scenes))
    for ax, scene in zip(axes, scenes):
        rows = _rows(nemd, scene)
        rates = [r["rate"] for r in rows]
        ax.errorbar(rates, [r["kT"] for r in rows], yerr=[r["kT_err"] for r in rows], marker="o", capsize=3,
                    color="k", label="kT")
        for k, axis in enumerate("xyz"):
            ax.plot(rates, [r[f"kT_{axis}"] for r in rows], marker="os^"[k], ls="--", color=f"C{k}", label=f"kT_{axis}")
        ax.axhline(1, color="0.5", lw=0.8)
        ax.set_xlabel("shear rate (1/ps)")
        ax.set_ylabel("peculiar kT (kT: ± 1 standard error)")
        ax.set_title(scene)
    legend_outside(fig, *figure_handles(fig), fontsize=8)
    save(fig, path)


def _pm(value, error, digits=3):
    return f"{value:.{digits}f} ± {error:.{digits}f}"


def _nemd_table(rows):
    lines = ["| rate | sampled | eta (NEMD) | kinetic | conservative | thermostat | slope/rate | profile rms/U "
             "| N1 = Pxx − Pyy | peculiar kT | kT_x, kT_y, kT_z |", "|" + "---|" * 11]
    for r in rows:
        lines.append(f"| {r['rate']:g} | {r['time']:g} | {_pm(r['eta'], r['eta_err'])} | {r['eta_kinetic']:.3f} "
                     f"| {r['eta_conservative']:.3f} | {r['eta_thermostat']:.3f} "
                     f"| {_pm(r['slope_ratio'], r['slope_ratio_err'], 4)} | {r['profile_rms']:.4f} "
                     f"| {_pm(r['N1'], r['N1_err'])} | {_pm(r['kT'], r['kT_err'], 4)} "
                     f"| {r['kT_x']:.4f}, {r['kT_y']:.4f}, {r['kT_z']:.4f} |")
    return lines


def _gk_table(results):
    lines = ["| series | sampled | Delta | fit starts; ends | eta (Green–Kubo) | statistical | systematic "
             "| tail tau | tail | earlier shoulder rule |", "|" + "---|" * 10]
    for name, r in results.items():
        lines.append(f"| {name} | {r['time']:g} | {r['block']:g} | {r['fit_start_from']:g}–{r['fit_start_to']:g}; "
                     f"{r['fit_end_from']:g}–{r['fit_end_to']:g} | "
                     f"{_pm(r['eta'], r['eta_err'])} | {r['eta_stat']:.3f} | {r['eta_sys']:.3f} | {r['tau']:.2f} | "
                     f"{r['tail']:.3f} | {r['eta_shoulder']:.3f} at {r['shoulder_time']:g} |")
    return lines


def _difference(a, a_err, b, b_err):
    combined = math.hypot(a_err, b_err)
    return a - b, combined, abs(a - b) / combined if combined > 0 else float("inf")


def temperature_flags(rows):
    """{rate: why} for the NEMD rows whose peculiar kT is off (further than KT_TOLERANCE from
    TARGET_KT) or too noisy to check (KT_SIGMAS standard errors wider than the tolerance)."""
    flags = {}
    for r in rows:
        kT, err = r["kT"], r["kT_err"]
        if not (math.isfinite(kT) and math.isfinite(err)):
            flags[r["rate"]] = f"peculiar kT {kT} ± {err} is not a number"
            continue
        off = abs(kT - TARGET_KT)
        sigmas = f" ({off / err:.1f} standard errors)" if err > 0 else ""
        if off > KT_TOLERANCE:
            flags[r["rate"]] = (f"peculiar kT {_pm(kT, err, 3)} is {off / TARGET_KT:.0%} from the target "
                                f"{TARGET_KT:g}{sigmas}, beyond the {KT_TOLERANCE:.0%} tolerance: the run is not "
                                f"at the thermostat's temperature (too short an equilibration, or a dt or rate "
                                f"too large), so its viscosity is not that of the fluid at kT {TARGET_KT:g}")
        elif KT_SIGMAS * err > KT_TOLERANCE:
            flags[r["rate"]] = (f"peculiar kT {_pm(kT, err, 3)}: {KT_SIGMAS} standard errors exceed the "
                                f"{KT_TOLERANCE:.0%} tolerance, too few samples to check the temperature "
                                f"(a longer --nemd-time)")
    return flags


def flags(nemd, gk):
    """Every flagged result of a run as short lines ("scene rate R: why", "scene: ..."): a peculiar
    kT off or unchecked (temperature_flags) and NEMD at the lowest rate disagreeing with
    Green–Kubo beyond AGREEMENT_SIGMAS."""
    found = []
    for scene in _scenes(nemd, gk):
        rows = _rows(nemd, scene)
        found += [f"{scene} rate {rate:g}: {why}" for rate, why in temperature_flags(rows).items()]
        if rows and scene in gk:
            low, total = rows[0], gk[scene]["total"]
            diff, err, z = _difference(low["eta"], low["eta_err"], total["eta"], total["eta_err"])
            if not z <= AGREEMENT_SIGMAS:
                found.append(f"{scene}: NEMD at rate {low['rate']:g} and Green–Kubo disagree ({diff:+.3f} ± {err:.3f}, "
                             f"{z:.1f} combined standard errors, more than {AGREEMENT_SIGMAS})")
    return found


def _checks(rows, results):
    """The report's checks, as lines: each rate's peculiar kT against the target, NEMD at the
    lowest rate against Green–Kubo, and the thermostat part of the stress present in Green–Kubo."""
    lines = []
    if rows:
        flagged = temperature_flags(rows)
        for rate, why in flagged.items():
            lines.append(f"- **Flagged**, rate {rate:g}: {why}.")
        fine = [r for r in rows if r["rate"] not in flagged]
        if fine:
            worst = max(fine, key=lambda r: abs(r["kT"] - TARGET_KT))
            where = "every rate" if not flagged else "rates " + ", ".join(f"{r['rate']:g}" for r in fine)
            lines.append(f"- Peculiar kT within {KT_TOLERANCE:.0%} of {TARGET_KT:g} at {where} (furthest "
                         f"{_pm(worst['kT'], worst['kT_err'], 4)} at rate {worst['rate']:g}).")
    if rows and results:
        low, total = rows[0], results["total"]
        diff, err, z = _difference(low["eta"], low["eta_err"], total["eta"], total["eta_err"])
        verdict = "agree" if z <= AGREEMENT_SIGMAS else "DISAGREE"
        lines.append(f"- NEMD at the lowest rate ({low['rate']:g}) minus Green–Kubo: {diff:+.3f} ± {err:.3f} "
                     f"({z:.1f} combined standard errors): they {verdict} within {AGREEMENT_SIGMAS}.")
    if results:
        lines.append(_thermostat_check(results["total"], results["total - thermostat"]))
    return lines


def _thermostat_check(total, without):
    """The line of _checks on the thermostat part: Green–Kubo with and without it, the
    difference's error from the jackknife of the paired differences where the segments are
    known (a report re-read from the CSV files has only each series' own error)."""
    diff = total["eta"] - without["eta"]
    if "jackknife" in total and "jackknife" in without:
        err = jackknife_error(np.asarray(total["jackknife"]) - np.asarray(without["jackknife"]))
        difference = f"difference {diff:+.3f} ± {err:.3f} statistical ({abs(diff) / err:.1f} sigma, paired jackknife)"
    else:
        difference = (f"difference {diff:+.3f} (its paired error needs the block series, gk_series_SCENE.npz, which "
                      "the CSV files do not hold)")
    return (f"- The dissipative and random (thermostat) stress is present: Green–Kubo from the total "
            f"{_pm(total['eta'], total['eta_err'])}, without the thermostat part "
            f"{_pm(without['eta'], without['eta_err'])}, "
            f"{difference}.")


def _scene_section(scene, rows, results):
    density = SCENES[scene]["density"]
    estimate = groot_warren_estimate(density)
    lines = [f"## {scene} (rho {density:g}, a {SCENES[scene]['a']:g}, gamma {FRICTION:g})", "",
             f"Groot–Warren kinetic-theory estimate (no conservative force): eta ≈ {estimate:.3f}.", ""]
    if results:
        lines += ["### Green–Kubo (equilibrium)", ""] + _gk_table(results) + [""]
    if rows:
        lines += ["### NEMD (Lees–Edwards)", "",
                  "eta per part is −<P_xy part>/rate (kinetic, conservative, thermostat = dissipative + random); "
                  "they sum to eta.", ""] + _nemd_table(rows) + [""]
    return lines + ["### Checks", ""] + _checks(rows, results) + [""]


METHODS = """Methods (see `openmmdpd/viscosity.py`): the integrator's pressure tensor
(docs/theory/pressure-tensor.md), read as block averages over Delta. NEMD errors: standard
error of the block series of P_xy from its statistical inefficiency (pymbar). Green–Kubo: eta =
V/kT Delta [C(0)/2 + sum_k C(k)], C averaged over xy, xz, yz; block averaging leaves this
integral unchanged (the zero-frequency power of a series is that of its block means); the
C(0)/2 term holds the random force's white-noise stress. The stress correlation falls fast (a
few tenths of a time unit) and then has a slow tail (about a tenth of eta, decay time 1 or
more) that the noise of single lags hides, so the integral is not read where it first looks
flat: for each window from a start t0 (5 in the fit-start range) to an end t1 (3 in the fit-end
range), C is fitted by A exp(-(t - t0)/tau) (least squares; tau scanned up to a quarter of the
window, a tau at that bound meaning the window limits the fit) and eta(t0, t1) = I(t0) + the
fit's sum beyond t0. The value is the mean over the 15 windows; its error adds in quadrature
the statistical error (jackknife over independent consecutive segments, the whole fit redone
with each left out) and a systematic one (half the spread over the windows). The earlier
shoulder rule (the first lag 2k with |I(2k) - I(k)| within 1 standard error) is listed for
comparison: where it reads before the tail it comes out low."""


def write_report(args, nemd, gk, seconds, source="the saved series"):
    """report.md and the charts in args.out; seconds None: re-read from `source`, not run."""
    out = args.out
    if nemd or gk:
        viscosity_chart(os.path.join(out, "viscosity.png"), nemd, gk)
    if gk:
        green_kubo_chart(os.path.join(out, "green_kubo.png"), gk)
    if nemd:
        temperature_chart(os.path.join(out, "temperature.png"), nemd)
    lines = ["# Shear viscosity: NEMD, Green–Kubo and the Groot–Warren estimate", "",
             f"`python3 -m openmmdpd.viscosity {' '.join(args.command)}` — {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, "
             f"{f're-read from {source}' if seconds is None else f'{seconds / 60:.1f} min'}; integrator {args.integrator}, dt {args.dt:g}, N {args.particles}, "
             f"{args.platform} platform ({args.threads} thread(s)), block Delta {args.block:g}, "
             f"equilibration {args.equilibrate:g} per run, seed {args.seed}. Reduced units (kT, rc, m = 1).", "",
             METHODS, ""]
    found = flags(nemd, gk)
    if found:
        lines += [f"**{len(found)} result(s) flagged** (see each scene's checks):", ""] + [f"- {f}" for f in found] + [""]
    else:
        lines += [f"No result flagged (the checks: a peculiar kT within {KT_TOLERANCE:.0%} of {TARGET_KT:g} at every "
                  f"rate, with {KT_SIGMAS} standard errors inside that tolerance; NEMD at the lowest rate and "
                  f"Green–Kubo within {AGREEMENT_SIGMAS} combined standard errors).", ""]
    for scene in _scenes(nemd, gk):
        lines += _scene_section(scene, _rows(nemd, scene), gk.get(scene))
    lines += ["Charts: `viscosity.png` (eta against rate), `green_kubo.png` (running integral and tail-fit value), "
              "`temperature.png` (peculiar kT against rate). Data: `nemd.csv`, `gk.csv`, `gk_running.csv`, and "
              "each scene's Green–Kubo block series `gk_series_SCENE.npz` (off-diagonal components of each part, "
              "float32), from which `--reanalyse` redoes the Green–Kubo analysis.", ""]
    with open(os.path.join(out, "report.md"), "w") as f:
        f.write("\n".join(lines))


if __name__ == "__main__":
    not_a_command("viscosity_report",
                  "It writes the report and charts of `python3 -m openmmdpd.viscosity`, which runs them; `python3 -m "
                  "openmmdpd.viscosity --reanalyse --out FOLDER` rewrites a finished run's report in seconds (see its "
                  "--help).")
