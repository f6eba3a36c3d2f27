"""Shear viscosity of a DPD fluid three ways: non-equilibrium (Lees–Edwards) over a sweep of
shear rates, Green–Kubo from an equilibrium run, and Groot–Warren's kinetic-theory estimate.

    /usr/bin/python3 -m openmmdpd.viscosity [--scene model-b gw-fluid] [--out results/viscosity]

Everything is in reduced units (kT = 1 kJ/mol, rc = 1 nm, m = 1 amu: time in ps, pressure in
kJ/mol/nm^3 = kT/rc^3, viscosity in kT ps/nm^3).  The pressure tensor is the integrator's own
(`setPressureTensorEnabled`, docs/theory/pressure-tensor.md), read as block averages over --block time
units (`openmmdpd.pressure`), in four parts: total, kinetic (peculiar velocities), conservative,
thermostat (dissipative + random).

NEMD: at each rate the System starts from the scene's positions with the imposed flow
rate (y - Ly/2) added to thermal velocities, equilibrates for --equilibrate, then samples for
--nemd-time: eta = -<P_xy>/rate with its standard error from the statistical inefficiency
(pymbar) of the block series; the velocity profile's least-squares slope over the rate and its
rms residual over U = rate Ly (openmmdpd.shear, a frame every --frame-every); the peculiar kT
and its three components.

Green–Kubo: at rate 0, eta = V/kT Delta [C(0)/2 + sum_{k>=1} C(k)], C the autocorrelation of
the block-averaged off-diagonal components (averaged over xy, xz, yz, without subtracting the
mean, which is 0 by symmetry), Delta = --block (the block series goes to gk_series_SCENE.npz,
from which --reanalyse redoes this analysis). Block averaging leaves the integral unchanged (the
zero-frequency power of a series is that of its block means), and the C(0)/2 term carries the
random force's white-noise stress, which has no correlation at lag >= 1.

DPD's stress correlation falls by an order of magnitude within a few tenths of a time unit and
then has a slow tail, about a tenth of eta with a decay time of 1 or more, smaller than the
noise of a single lag: the running integral I(t) looks flat early and keeps creeping up, so
reading it where it first stops changing (the earlier rule, shoulder_lag) comes out low. The
rule here fits the tail: for each window from a start t0 (5 spread over --gk-fit-start, past
the fast decay) to an end t1 (3 spread over --gk-fit-end), C is fitted by A exp(-(t - t0)/tau)
(least squares, tau scanned on a grid up to a quarter of the window), and eta(t0, t1) = I(t0) +
the fit's sum beyond t0. eta is the mean over the 15 windows; its error adds in quadrature the
statistical error (jackknife: the whole estimate redone with each of --segments consecutive
segments left out) and a systematic one for the choice of window (half the spread of eta(t0,
t1)). The same estimate without the thermostat part (total - thermostat) shows that the
dissipative and random stress matters.
"""
import csv
import os
import sys
import time

import numpy as np
import openmm
from openmm import unit

from . import options, shear
from .analysis import jackknife_error, standard_error
from .catalog import integrators
from .charts import use_file_backend
from .pressure import PARTS, check_integrator, pressure_tensor
from .scenes import build_scene
from .units import KT_TEMPERATURE, kT_from_temperature
from .viscosity_fluids import SCENES
from .viscosity_report import flags, write_report

OFF_DIAGONAL = slice(3, 6)  # xy, xz, yz in (xx, yy, zz, xy, xz, yz)
PROFILE_BINS = 10
NEMD_COLUMNS = ["scene", "integrator", "dt", "rate", "time", "eta", "eta_err", "eta_kinetic", "eta_conservative",
                "eta_thermostat", "Pxy", "Pxy_err", "N1", "N1_err", "slope_ratio", "slope_ratio_err", "profile_rms",
                "kT", "kT_err", "kT_x", "kT_y", "kT_z"]
GK_COLUMNS = ["scene", "integrator", "dt", "series", "time", "block", "fit_start_from", "fit_start_to", "fit_end_from",
              "fit_end_to", "eta", "eta_err", "eta_stat", "eta_sys", "tau", "tail", "shoulder_time", "eta_shoulder"]
TAU_GRID = 200  # decay times the tail fit scans (about 2 % apart with the defaults)
FIT_STARTS = 5  # tail-fit starts spread over --gk-fit-start
FIT_ENDS = 3  # and ends over --gk-fit-end


# --- Green–Kubo ----------------------------------------------------------------------------------

def autocorrelation(series, max_lag):
    """C(k) = <x(t) x(t+k)> for k = 0..max_lag of the columns of series (n, m), averaged over
    every origin with a full lag and over the columns; the mean is not subtracted."""
    x = np.asarray(series, dtype=float)
    x = x.reshape(len(x), -1)
    n = len(x)
    if not 0 <= max_lag < n:
        raise ValueError(f"max_lag must be in [0, {n - 1}] for {n} samples, got {max_lag}")
    size = 1 << int(np.ceil(np.log2(2 * n)))
    spectrum = np.fft.rfft(x, n=size, axis=0)
    c = np.fft.irfft(np.abs(spectrum) ** 2, n=size, axis=0)[:max_lag + 1].mean(axis=1)
    return c / (n - np.arange(max_lag + 1))


def running_integral(correlation, interval):
    """I(k) = Delta [C(0)/2 + sum_{j=1..k} C(j)]: the discrete integral of C to lag k, whose
    lag-0 half-term holds a white-noise part's whole contribution."""
    c = np.asarray(correlation, dtype=float)
    return interval * (np.cumsum(c) - 0.5 * c[0])


def shoulder_lag(running, segment_running, sigmas=1.0):
    """The earlier rule, kept to show its bias: the first lag L = 2k (k >= 1) with |I(2k) - I(k)|
    within `sigmas` standard errors of 0 (the error from the segments, rows of segment_running);
    the longest even lag if there is none.  Where C has a slow tail small next to the noise of
    a single lag, this shoulder comes before the tail is integrated and reads too low
    (test_viscosity: 5 % low on series with a 10 % tail)."""
    running, segments = np.asarray(running, dtype=float), np.asarray(segment_running, dtype=float)
    for k in range(1, (len(running) - 1) // 2 + 1):
        rise = segments[:, 2 * k] - segments[:, k]
        if abs(running[2 * k] - running[k]) <= sigmas * rise.std(ddof=1) / np.sqrt(len(rise)):
            return 2 * k
    return max(2, (len(running) - 1) // 2 * 2)


def exponential_tail(correlation, start, end, interval):
    """(A, tau, tail) of the least-squares A exp(-(t - t0)/tau) to C from lag `start` (t0) to
    lag `end`: tau scanned on a log grid from Delta to a quarter of the fit window (which then
    spans four decay times, so the data and not the extrapolation fix it), A linear at each tau;
    tail = Delta sum_{k > start} A q^(k - start), q = exp(-Delta/tau), the rest of the integral."""
    y = np.asarray(correlation, dtype=float)[start:end + 1]
    taus = np.geomspace(interval, max(interval, (len(y) - 1) * interval / 4), TAU_GRID)
    shapes = np.exp(-np.outer(1 / taus, np.arange(len(y)) * interval))
    amplitudes = shapes @ y / np.einsum("ij,ij->i", shapes, shapes)
    best = np.argmin(np.sum((y - amplitudes[:, None] * shapes) ** 2, axis=1))
    a, tau = float(amplitudes[best]), float(taus[best])
    q = np.exp(-interval / tau)
    return a, tau, interval * a * q / (1 - q)


def tail_fit_estimates(correlation, interval, windows):
    """eta(t0, t1) = I(t0) + the tail of the exponential fitted from t0 to t1, for each window
    (start lag, end lag)."""
    running = running_integral(correlation, interval)
    return np.array([running[k] + exponential_tail(correlation, k, end, interval)[2] for k, end in windows])


def fit_windows(fit_start, fit_end, interval, max_lag):
    """The (start, end) lags of the tail fits: FIT_STARTS starts evenly over the times fit_start,
    FIT_ENDS ends evenly in log over fit_end (both cut at max_lag), each window at least 4 lags;
    the middle window first."""
    def lags(times, count, spacing):
        first, last = (min(max(1, round(t / interval)), max_lag) for t in times)
        return np.unique(spacing(first, max(first, last), count).round().astype(int))
    starts = lags(fit_start, FIT_STARTS, np.linspace)
    ends = lags(fit_end, FIT_ENDS, np.geomspace)
    middle = (starts[len(starts) // 2], ends[len(ends) // 2])
    windows = [(k, e) for k in starts for e in ends if e - k >= 4]
    if not windows:
        raise ValueError(f"no tail-fit window of 4 lags: starts {starts * interval}, ends {ends * interval}")
    return sorted(windows, key=lambda w: w != middle)


def green_kubo(series, interval, scale=1.0, max_lag=None, segments=8, fit_start=(0.5, 1.5), fit_end=(5.0, 20.0)):
    """Green–Kubo integral scale * Delta [C(0)/2 + sum C(k)] of series (n, m) sampled every
    interval, its columns' correlations averaged, with C's tail fitted by an exponential
    (tail_fit_estimates) over every window of fit_windows: eta is the mean over the windows,
    eta_stat its jackknife error over `segments` consecutive segments, eta_sys half the spread
    over the windows, eta_err the two in quadrature; with tau and tail (the middle window's
    fit), the earlier shoulder rule's value (eta_shoulder, shoulder_lag), the lags, C and running
    integral (scaled) for charts, and the jackknife's estimates (one per segment left out)."""
    x = np.asarray(series, dtype=float)
    x = x.reshape(len(x), -1)
    if segments < 2 or len(x) // segments < 6:
        raise ValueError(f"need at least 2 segments of 6 samples; got {len(x)} samples for {segments} segments")
    max_lag = min(len(x) // segments - 1, max_lag if max_lag is not None else len(x) // segments - 1)
    if max_lag < 5:
        raise ValueError(f"max_lag must be >= 5, got {max_lag}")
    c = autocorrelation(x, max_lag)
    parts = np.array([autocorrelation(part, max_lag) for part in np.array_split(x, segments)])
    windows = fit_windows(fit_start, fit_end, interval, max_lag)
    each = scale * tail_fit_estimates(c, interval, windows)
    left_out = np.array([scale * tail_fit_estimates(np.delete(parts, i, axis=0).mean(axis=0), interval, windows).mean()
                         for i in range(segments)])
    stat, sys_err = jackknife_error(left_out), float(each.max() - each.min()) / 2
    _, tau, tail = exponential_tail(c, *windows[0], interval)
    running = scale * running_integral(c, interval)
    shoulder = shoulder_lag(running, np.array([scale * running_integral(p, interval) for p in parts]))
    starts, ends = (np.array([w[k] for w in windows]) * interval for k in (0, 1))
    return dict(fit_start_from=starts.min(), fit_start_to=starts.max(), fit_end_from=ends.min(), fit_end_to=ends.max(),
                eta=float(each.mean()), eta_err=float(np.hypot(stat, sys_err)), eta_stat=stat, eta_sys=sys_err,
                tau=float(tau),
                tail=float(scale * tail), shoulder_time=shoulder * interval, eta_shoulder=float(running[shoulder]),
                lags=np.arange(max_lag + 1) * interval, correlation=c, running=running, jackknife=left_out)


# --- runs ----------------------------------------------------------------------------------------

def _platform(args):
    properties = {"Threads": str(args.threads)} if args.platform == "CPU" else {}
    return openmm.Platform.getPlatformByName(args.platform), properties


def start_run(scene, args, rate):
    """(integrator, Context, box height) at the scene's positions, thermal velocities with no net
    momentum plus the imposed flow rate (y - Ly/2), the pressure tensor enabled."""
    integrator = integrators(None)[args.integrator](args.dt)
    check_integrator(integrator)
    integrator.setRandomNumberSeed(args.seed)
    integrator.setShearRate(rate)
    integrator.setPressureTensorEnabled(True)
    context = openmm.Context(scene.system, integrator, *_platform(args))
    positions = scene.positions.value_in_unit(unit.nanometer)
    height = scene.system.getDefaultPeriodicBoxVectors()[1][1].value_in_unit(unit.nanometer)
    context.setPositions(positions)
    context.setVelocitiesToTemperature(KT_TEMPERATURE, args.seed)
    shear.remove_net_momentum(context)
    shear.impose_flow(context, rate)
    return integrator, context, height


def sample_blocks(integrator, context, args, blocks, rate=0.0, height=1.0):
    """Equilibrates, then (tensors (blocks, parts, 6) of block averages over args.block, frames):
    a frame every args.frame_every (None: no frames) is (slope, residuals, kT, (kT_x, kT_y, kT_z))."""
    integrator.step(round(args.equilibrate / args.dt))
    steps = max(1, round(args.block / args.dt))
    every = max(1, round(args.frame_every / (steps * args.dt))) if args.frame_every else 0
    integrator.resetPressureTensor()
    tensors, frames = np.empty((blocks, len(PARTS), 6)), []
    for k in range(blocks):
        integrator.step(steps)
        tensors[k] = [pressure_tensor(integrator, part) for part in range(len(PARTS))]
        integrator.resetPressureTensor()
        if every and (k + 1) % every == 0:
            frames.append(_frame(context, rate, height))
    return tensors, frames


def _frame(context, rate, height):
    state = context.getState(getPositions=True, getVelocities=True)
    r, v = state.getPositions(asNumpy=True), state.getVelocities(asNumpy=True)
    slope, residuals = shear.profile_slope(*shear.velocity_profile(r, v, height, PROFILE_BINS))
    kT, components = shear.peculiar_temperature(r, v, np.ones(len(r)), rate, height)
    return slope, residuals, kT, components


def _blocks(total_time, args):
    return max(2, round(total_time / (max(1, round(args.block / args.dt)) * args.dt)))


def nemd_row(scene, args, rate):
    """One rate: the NEMD_COLUMNS of a sheared run (viscosity per part, profile, peculiar kT)."""
    integrator, context, height = start_run(scene, args, rate)
    tensors, frames = sample_blocks(integrator, context, args, _blocks(args.nemd_time, args), rate, height)
    pxy = tensors[:, 0, 3]
    n1 = tensors[:, 0, 0] - tensors[:, 0, 1]
    slopes = np.array([f[0] for f in frames]) / rate
    kT = np.array([f[2] for f in frames])
    components = np.mean([f[3] for f in frames], axis=0)
    residuals = np.mean([f[1] for f in frames], axis=0)
    row = dict(scene=args.scene_name, integrator=args.integrator, dt=args.dt, rate=rate,
               time=len(pxy) * round(args.block / args.dt) * args.dt,
               eta=-pxy.mean() / rate, eta_err=standard_error(pxy) / rate, Pxy=pxy.mean(), Pxy_err=standard_error(pxy),
               N1=n1.mean(), N1_err=standard_error(n1), slope_ratio=slopes.mean(), slope_ratio_err=standard_error(slopes),
               profile_rms=float(np.sqrt(np.mean(residuals ** 2)) / (rate * height)),
               kT=kT.mean(), kT_err=standard_error(kT), kT_x=components[0], kT_y=components[1], kT_z=components[2])
    for part in (1, 2, 3):
        row[f"eta_{PARTS[part]}"] = -tensors[:, part, 3].mean() / rate
    return row


def green_kubo_runs(scene, args):
    """An equilibrium run's Green–Kubo results (green_kubo_results); its block series is saved
    in args.out/gk_series_SCENE.npz (see --reanalyse)."""
    integrator, context, _ = start_run(scene, args, 0.0)
    tensors, _ = sample_blocks(integrator, context, args, _blocks(args.gk_time, args))
    interval = round(args.block / args.dt) * args.dt
    box = scene.system.getDefaultPeriodicBoxVectors()
    volume = box[0][0] * box[1][1] * box[2][2] / unit.nanometer**3
    kT = kT_from_temperature(integrator.getTemperature())
    off_diagonal = tensors[:, :, OFF_DIAGONAL]
    # Only what Green–Kubo reads, in float32: about 48 bytes a block keeps the file commit-sized.
    np.savez_compressed(os.path.join(args.out, f"gk_series_{args.scene_name}.npz"), interval=interval,
                        volume=volume, kT=kT, off_diagonal=off_diagonal.astype(np.float32))
    return green_kubo_results(off_diagonal, interval, volume / kT, args)


def green_kubo_results(off, interval, scale, args):
    """{series name: green_kubo dict} of the block tensors' off-diagonal components (blocks,
    parts, 3: xy, xz, yz) for the total, each part, and the total without the thermostat part."""
    series = {name: off[:, k] for k, name in enumerate(PARTS)}
    series["total - thermostat"] = off[:, 0] - off[:, 3]
    max_lag = max(2, round(args.gk_max_lag / interval))
    results = {name: green_kubo(x, interval, scale, max_lag, args.segments, args.gk_fit_start, args.gk_fit_end)
               for name, x in series.items()}
    for result in results.values():
        result.update(time=len(off) * interval, block=interval)
    return results


# --- output --------------------------------------------------------------------------------------

def _format(value):
    return f"{value:.6g}" if isinstance(value, float) else value


def write_csvs(args, nemd, gk):
    """nemd.csv (one row per scene and rate), gk.csv (one row per scene and series) and
    gk_running.csv (lag time, C and the running integral of each scene's total and
    total - thermostat series)."""
    with open(os.path.join(args.out, "nemd.csv"), "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=NEMD_COLUMNS)
        writer.writeheader()
        writer.writerows({k: _format(v) for k, v in row.items()} for row in nemd)
    with open(os.path.join(args.out, "gk.csv"), "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=GK_COLUMNS, extrasaction="ignore")
        writer.writeheader()
        for scene, results in gk.items():
            for name, r in results.items():
                row = dict(r, scene=scene, integrator=args.integrator, dt=args.dt, series=name)
                writer.writerow({k: _format(v) for k, v in row.items() if k in GK_COLUMNS})
    with open(os.path.join(args.out, "gk_running.csv"), "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(["scene", "series", "lag_time", "C", "eta_running"])
        for scene, results in gk.items():
            for name in ("total", "total - thermostat"):
                r = results[name]
                writer.writerows([scene, name, _format(float(t)), _format(float(c)), _format(float(i))]
                                 for t, c, i in zip(r["lags"], r["correlation"], r["running"]))


def schedule(args):
    """The runs in order, (scene, rate or None for Green–Kubo): each scene's Green–Kubo run and
    lowest rate first (the pair the agreement check needs), then the other rates, so that a
    run cut short has the comparison for every scene."""
    first = [(name, rate) for name in args.scene for rate in ([None] if args.gk_time > 0 else []) + args.rates[:1]]
    return first + [(name, rate) for rate in args.rates[1:] for name in args.scene]


def run(args):
    """The runs of schedule(args); the outputs are rewritten after each, so that a run cut
    short leaves what it finished."""
    os.makedirs(args.out, exist_ok=True)
    began = time.perf_counter()
    nemd, gk = [], {}
    for name, rate in schedule(args):
        args.scene_name = name
        scene = build_scene("soft", num_particles=args.particles, seed=args.seed, **SCENES[name])
        if rate is None:
            _say(args, f"{name}: Green–Kubo, {args.gk_time:g} time units")
            gk[name] = green_kubo_runs(scene, args)
        else:
            _say(args, f"{name}: NEMD at rate {rate:g}, {args.nemd_time:g} time units")
            nemd.append(nemd_row(scene, args, rate))
        write_csvs(args, nemd, gk)
        write_report(args, nemd, gk, time.perf_counter() - began)
    return nemd, gk


def _read_csv(path):
    """The rows of one of write_csvs' files, numbers as floats; [] if there is no such file."""
    if not os.path.exists(path):
        return []
    with open(path) as f:
        return [{k: v if k in ("scene", "integrator", "series") else float(v) for k, v in row.items()}
                for row in csv.DictReader(f)]


def green_kubo_from_csvs(out, scene):
    """{series name: result} of the scene as gk.csv and gk_running.csv in `out` hold it (None if
    they do not): the values of gk.csv, and the lags, C and running integral of the series that
    gk_running.csv keeps (total, total - thermostat); not the segments' running integrals, which
    only the block series gives."""
    results = {row["series"]: dict(row)
               for row in _read_csv(os.path.join(out, "gk.csv")) if row["scene"] == scene}
    running = [row for row in _read_csv(os.path.join(out, "gk_running.csv")) if row["scene"] == scene]
    for name, result in results.items():
        mine = [row for row in running if row["series"] == name]
        if mine:
            result.update(lags=np.array([row["lag_time"] for row in mine]),
                          correlation=np.array([row["C"] for row in mine]),
                          running=np.array([row["eta_running"] for row in mine]))
    return results or None


def reanalyse(args):
    """Rewrites the outputs in args.out from what a run left there: nemd.csv, and for each scene
    its saved Green–Kubo block series (a new Green–Kubo rule, fit ranges or --segments without
    rerunning) or, where the series is not kept, the Green–Kubo values of gk.csv and
    gk_running.csv as they are."""
    nemd = _read_csv(os.path.join(args.out, "nemd.csv"))
    gk, sources = {}, set()
    for name in args.scene:
        path = os.path.join(args.out, f"gk_series_{name}.npz")
        if os.path.exists(path):
            saved = np.load(path)
            volume = float(saved["volume"]) if "volume" in saved else args.particles / SCENES[name]["density"]
            kT = float(saved["kT"]) if "kT" in saved else 1.0
            off = saved["off_diagonal"] if "off_diagonal" in saved else saved["tensors"][:, :, OFF_DIAGONAL]
            gk[name] = green_kubo_results(off.astype(float), float(saved["interval"]), volume / kT, args)
            sources.add("the saved series")
        elif kept := green_kubo_from_csvs(args.out, name):
            gk[name] = kept
            sources.add("the CSV files")
    write_csvs(args, nemd, gk)
    write_report(args, nemd, gk, None, " and ".join(sorted(sources, reverse=True)) or "the CSV files")
    return nemd, gk


def _say(args, message):
    if not args.quiet:
        print(f"[{time.strftime('%H:%M:%S')}] {message}", flush=True)


# How long a run with the defaults takes, for --help, scaled from the committed run
# (docs/results/viscosity): 1500 time units of Green–Kubo and 3 rates of 200 per scene, with 10
# of equilibration a run, took 12-13 minutes a scene (37 for its three) on one thread.
DURATION = ("With the defaults (scene model-b, N 4000, dt 0.01, 5 rates of 400 time units and 800 for "
            "Green–Kubo, one thread) a run takes about 15-20 minutes per scene on one core (scaled from "
            "the committed run's 12-13 minutes a scene for 2140 time units); the time grows with "
            "--particles times the total time (--nemd-time per rate, --gk-time, --equilibrate per run) "
            "over --dt, and with each --scene. --quick takes seconds; --reanalyse, no runs, seconds.")

# --quick (options.add_quick)
QUICK = dict(particles=300, rates=[0.5], nemd_time=2.0, gk_time=4.0, equilibrate=0.5, frame_every=0.5,
             gk_max_lag=0.5, segments=4, gk_fit_start=[0.1, 0.2], gk_fit_end=[0.4, 0.5])


def _parser():
    parser = options.parser("viscosity", __doc__.split("\n\n")[0], DURATION)
    add = parser.add_argument
    add("--scene", nargs="+", default=["model-b"], choices=sorted(SCENES),
        help="model-a: rho 4, a 0; model-b: rho 4, a 25; gw-fluid: Groot–Warren's rho 3, a 25 (gamma 4.5 all)")
    add("--integrator", default="GW", help="a name from openmmdpd.catalog (GW, S1, Lowe, PairOU, ...)")
    add("--dt", type=float, default=0.01, help="time step (ps = reduced time)")
    add("-N", "--particles", type=int, default=4000, help="N")
    add("--rates", type=float, nargs="*", default=[0.05, 0.1, 0.2, 0.3, 0.5], help="shear rates (1/ps) of the NEMD sweep")
    add("--nemd-time", type=float, default=400.0, help="time sampled at each rate")
    add("--gk-time", type=float, default=800.0, help="time sampled at equilibrium for Green–Kubo (0: none)")
    add("--equilibrate", type=float, default=10.0, help="time each run equilibrates before sampling")
    add("--block", type=float, default=0.05, help="time of a block average of the tensor (the GK interval Delta)")
    add("--frame-every", type=float, default=1.0, help="time between frames (velocity profile, peculiar kT)")
    add("--gk-max-lag", type=float, default=20.0, help="longest lag time of the correlation")
    add("--gk-fit-start", type=float, nargs=2, default=[0.5, 1.5], metavar=("FROM", "TO"),
        help="range of lag times where the exponential fit of the Green–Kubo tail starts (5 starts in it)")
    add("--gk-fit-end", type=float, nargs=2, default=[5.0, 20.0], metavar=("FROM", "TO"),
        help="range of lag times where it ends (3 ends, cut at --gk-max-lag); the value is the mean over the "
             "15 fits, its systematic error half their spread")
    add("--segments", type=int, default=8, help="independent segments giving the Green–Kubo jackknife error")
    options.add_quick(parser, QUICK)
    add("--platform", default="CPU", help="OpenMM platform")
    add("--threads", type=int, default=1, help="CPU platform threads")
    add("--seed", type=int, default=2024, help="seed of the start and of the integrator")
    add("--out", default=os.path.join("results", "viscosity"), help="output folder")
    add("--quiet", action="store_true", help="no progress lines")
    add("--reanalyse", action="store_true",
        help="no runs: rewrite the outputs from --out's nemd.csv and saved series (a scene without its series: "
             "from gk.csv and gk_running.csv, as they are)")
    return parser


def main(argv=None):
    use_file_backend()
    args = options.parse_args(_parser(), argv, QUICK)
    args.command = list(sys.argv[1:] if argv is None else argv)
    if args.integrator not in integrators(None) or args.integrator == "Langevin":
        raise SystemExit(f"unknown or non-DPD integrator {args.integrator!r}; available: "
                         f"{', '.join(n for n in integrators(None) if n != 'Langevin')}")
    start = time.perf_counter()
    if args.reanalyse:
        nemd, gk = reanalyse(args)
        print(f"outputs in {args.out}/ rewritten from its nemd.csv and gk_series_*.npz (else gk.csv, gk_running.csv)")
        _print_flags(nemd, gk)
        return 0
    nemd, gk = run(args)
    print(f"{len(nemd)} NEMD runs and {len(args.scene) if args.gk_time > 0 else 0} Green–Kubo runs in "
          f"{time.perf_counter() - start:.0f} s; results, charts and report in {args.out}/")
    _print_flags(nemd, gk)
    return 0


def _print_flags(nemd, gk):
    for line in flags(nemd, gk):
        print(f"FLAGGED: {line}")


if __name__ == "__main__":
    sys.exit(main())
