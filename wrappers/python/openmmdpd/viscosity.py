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
mean, which is 0 by symmetry), Delta = --block (the block series goes to gk_series_SCENE.npz).
Block averaging leaves the integral unchanged (the zero-frequency power of a series is that of
its block means), and the C(0)/2 term carries the random force's white-noise stress, which has
no correlation at lag >= 1. The plateau is read at the first lag 2k such that |I(2k) - I(k)| is
within 1 standard error of 0 (the integral has stopped changing; DPD's stress correlation has
a slow tail that keeps it rising past C's first zero); the error is the spread over --segments
independent consecutive segments, each integrated to the same lag. The same integral without
the thermostat part (total - thermostat) is reported to show that the dissipative and random
stress matters.
"""
import csv
import os
import sys
import time

import numpy as np
import openmm
from openmm import unit

from . import options, shear
from .analysis import standard_error
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
GK_COLUMNS = ["scene", "integrator", "dt", "series", "time", "block", "plateau_time", "eta", "eta_err", "eta_2lag",
              "eta_4lag"]


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


def plateau_lag(running, segment_running, sigmas=1.0):
    """The first lag L = 2k (k >= 1) over whose second half the integral has stopped changing:
    |I(2k) - I(k)| within `sigmas` standard errors of 0, the error from the same difference
    over the segments (rows of segment_running); the longest even lag if it never does.  Read
    at 2k rather than k, so that what was still rising within the noise is included.  A slowly
    decaying tail keeps DPD's integral rising past C's first zero: the first zero reads too low."""
    running, segments = np.asarray(running, dtype=float), np.asarray(segment_running, dtype=float)
    for k in range(1, (len(running) - 1) // 2 + 1):
        rise = segments[:, 2 * k] - segments[:, k]
        if abs(running[2 * k] - running[k]) <= sigmas * rise.std(ddof=1) / np.sqrt(len(rise)):
            return 2 * k
    return max(2, (len(running) - 1) // 2 * 2)


def green_kubo(series, interval, scale=1.0, max_lag=None, segments=8):
    """Green–Kubo integral scale * Delta [C(0)/2 + sum C(k)] of series (n, m) sampled every
    interval, its columns' correlations averaged: a dict with the plateau lag (plateau_lag), the
    integral there with its standard error from the spread over `segments` consecutive segments,
    the values at twice and four times the lag, the lags, C and running integral (scaled) for
    charts, and each segment's running integral (rows)."""
    x = np.asarray(series, dtype=float)
    x = x.reshape(len(x), -1)
    if segments < 2 or len(x) // segments < 3:
        raise ValueError(f"need at least 2 segments of 3 samples; got {len(x)} samples for {segments} segments")
    max_lag = min(len(x) // segments - 1, max_lag if max_lag is not None else len(x) // segments - 1)
    if max_lag < 2:
        raise ValueError(f"max_lag must be >= 2, got {max_lag}")
    c = autocorrelation(x, max_lag)
    running = scale * running_integral(c, interval)
    per_segment = np.array([scale * running_integral(autocorrelation(part, max_lag), interval)
                            for part in np.array_split(x, segments)])
    lag = plateau_lag(running, per_segment)
    return dict(lag=lag, plateau_time=lag * interval, eta=float(running[lag]),
                eta_err=float(per_segment[:, lag].std(ddof=1) / np.sqrt(segments)),
                eta_2lag=float(running[min(2 * lag, max_lag)]), eta_4lag=float(running[min(4 * lag, max_lag)]),
                lags=np.arange(max_lag + 1) * interval, correlation=c, running=running, segment_running=per_segment)


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
    v = context.getState(getVelocities=True).getVelocities(asNumpy=True).value_in_unit(unit.nanometer / unit.picosecond)
    v -= v.mean(axis=0)
    v[:, 0] += shear.streaming_velocity(positions[:, 1], rate, height)
    context.setVelocities(v)
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
    np.savez_compressed(os.path.join(args.out, f"gk_series_{args.scene_name}.npz"), interval=interval,
                        volume=volume, kT=kT, tensors=tensors.astype(np.float32))
    return green_kubo_results(tensors, interval, volume / kT, args)


def green_kubo_results(tensors, interval, scale, args):
    """{series name: green_kubo dict} of block tensors (blocks, parts, 6) for the total, each
    part, and the total without the thermostat part."""
    off = tensors[:, :, OFF_DIAGONAL]
    series = {name: off[:, k] for k, name in enumerate(PARTS)}
    series["total - thermostat"] = off[:, 0] - off[:, 3]
    max_lag = max(2, round(args.gk_max_lag / interval))
    results = {name: green_kubo(x, interval, scale, max_lag, args.segments) for name, x in series.items()}
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
    results = {row["series"]: dict(row, lag=round(row["plateau_time"] / row["block"]))
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
    its saved Green–Kubo block series (a new plateau rule or --segments without rerunning) or,
    where the series is not kept, the Green–Kubo values of gk.csv and gk_running.csv as they are."""
    nemd = _read_csv(os.path.join(args.out, "nemd.csv"))
    gk, sources = {}, set()
    for name in args.scene:
        path = os.path.join(args.out, f"gk_series_{name}.npz")
        if os.path.exists(path):
            saved = np.load(path)
            volume = float(saved["volume"]) if "volume" in saved else args.particles / SCENES[name]["density"]
            kT = float(saved["kT"]) if "kT" in saved else 1.0
            gk[name] = green_kubo_results(saved["tensors"].astype(float), float(saved["interval"]), volume / kT, args)
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


# How long a run with the defaults takes, for --help: 286 000 steps of N = 4000 with the pressure
# tensor sampled per scene (a GW step at N = 32 000 runs at 113-120 steps/s on one thread, and
# sampling the tensor makes it 2.2 times as long: docs/benchmarks.md).
DURATION = ("With the defaults (scene model-b, N 4000, dt 0.01, 5 rates of 400 time units and 800 for "
            "Green–Kubo, one thread) a run takes about 10-15 minutes per scene on one core (an estimate "
            "from the measured step rates, not a timed run); the time grows with --particles times the "
            "total time (--nemd-time per rate, --gk-time, --equilibrate per run) over --dt, and with each "
            "--scene. --quick takes seconds; --reanalyse, no runs, seconds.")

# --quick (options.add_quick)
QUICK = dict(particles=300, rates=[0.5], nemd_time=2.0, gk_time=4.0, equilibrate=0.5, frame_every=0.5,
             gk_max_lag=0.5, segments=4)


def _parser():
    parser = options.parser("viscosity", __doc__.split("\n\n")[0], DURATION)
    add = parser.add_argument
    add("--scene", nargs="+", default=["model-b"], choices=sorted(SCENES),
        help="model-b: rho 4, a 25; gw-fluid: Groot–Warren's rho 3, a 25 (gamma 4.5 both)")
    add("--integrator", default="GW", help="a name from openmmdpd.catalog (GW, S1, Lowe, PairOU, ...)")
    add("--dt", type=float, default=0.01, help="time step (ps = reduced time)")
    add("-N", "--particles", type=int, default=4000, help="N")
    add("--rates", type=float, nargs="*", default=[0.05, 0.1, 0.2, 0.3, 0.5], help="shear rates (1/ps) of the NEMD sweep")
    add("--nemd-time", type=float, default=400.0, help="time sampled at each rate")
    add("--gk-time", type=float, default=800.0, help="time sampled at equilibrium for Green–Kubo (0: none)")
    add("--equilibrate", type=float, default=10.0, help="time each run equilibrates before sampling")
    add("--block", type=float, default=0.05, help="time of a block average of the tensor (the GK interval Delta)")
    add("--frame-every", type=float, default=1.0, help="time between frames (velocity profile, peculiar kT)")
    add("--gk-max-lag", type=float, default=10.0, help="longest lag time of the correlation")
    add("--segments", type=int, default=8, help="independent segments giving the Green–Kubo error")
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
