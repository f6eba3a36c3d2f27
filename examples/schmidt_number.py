"""The Schmidt number of the standard DPD fluid (rho 3, a 25, gamma 4.5, kT 1, rc 1) against
the thermostat's weight exponent s (wD = (1 - r/rc)^s) and with transverse friction
(gamma_perp = gamma, its weight standard): the shear viscosity eta from a
Lees-Edwards NEMD run at one shear rate, the self-diffusion coefficient D from the mean
squared displacement at equilibrium, and Sc = eta / (rho D), each with its standard error,
beside the kinetic-theory estimates for the same weight.  CPU platform, ShardlowIntegrator S1;
a CSV and a Markdown report (report.md) into docs/results/schmidt-number/.

    PYTHONPATH=build/python /usr/bin/python3 examples/schmidt_number.py [--quick] [--out DIR]

eta = -<P_xy> / rate, the tensor averaged over blocks of BLOCK time whose means give the error
(pymbar's statistical inefficiency).  D is the slope / 6 of the MSD over lags of 10 to 30 ps
(openmmdpd.compare.diffusion), its error the spread of D over 8 interleaved sets of particles.  eta_T,
from the same equilibrium run, is the viscosity the decay of the transverse momentum current
at the box's smallest wavevector gives (openmmdpd.dynamics): no shear and no pressure tensor,
so it checks eta independently, the more so with transverse friction, whose pair forces are
not central and whose stress the pressure tensor must read in the right order.

Kinetic theory (Groot and Warren 1997 for s = 2, the same integrals for any s): a particle's
friction zeta = (rho / 3) int (gamma wD + 2 gamma_perp wD_perp) 4 pi r^2 dr (the trace of a
pair's friction matrix over 3), with int (1 - r)^s 4 pi r^2 dr = 8 pi / ((s+1)(s+2)(s+3)), so
D = kT / zeta; eta = rho D / 2 + (rho^2 / 30) int (gamma wD + 4 gamma_perp wD_perp) 4 pi r^4 dr,
int (1 - r)^s 4 pi r^4 dr = 96 pi / ((s+1)(s+2)(s+3)(s+4)(s+5)): in planar shear a pair's
relative velocity rate y_ij along x gives the friction along e the stress r_y F_x ~ e_x^2 e_y^2,
1/15 on average over directions, and the friction across e ~ e_y^2 (1 - e_x^2), 4/15.
It leaves out the conservative force and correlated collisions, so at a = 25 it is a guide to
the trend, not a target.
"""
import argparse
import csv
import math
import os
import time

import numpy as np
import openmm

import openmmdpd
from openmmdpd import dynamics, scenes
from openmmdpd.analysis import grouped_squared_displacement, standard_error
from openmmdpd.compare import diffusion_with_error

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "..", "docs", "results", "schmidt-number")
DENSITY, A, GAMMA, KT = 3.0, 25.0, 4.5, 1.0
BLOCK = 1.0  # ps of one pressure-tensor block
FRAME, CURRENT = 0.5, 0.1  # ps between the MSD's frames and between the transverse currents' samples
# (s, gamma_perp): the weight exponent along e, and the transverse friction (its exponent 2)
FULL = dict(particles=3000, dt=0.02, rate=0.2, equilibrate=10.0, diffusion_time=200.0, nemd_time=400.0,
            cases=[(2.0, 0.0), (1.0, 0.0), (0.5, 0.0), (2.0, GAMMA)])
QUICK = dict(particles=500, dt=0.02, rate=0.5, equilibrate=1.0, diffusion_time=4.0, nemd_time=6.0,
             cases=[(2.0, 0.0), (0.5, 0.0), (2.0, GAMMA)])


def kinetic_theory(s, gamma_perp=0.0):
    """(D, eta, Sc) of kinetic theory for wD = (1 - r)^s and transverse friction gamma_perp with
    wD_perp = (1 - r)^2 at DENSITY, GAMMA, KT, rc = 1."""
    def second(p):
        return 8 * math.pi / ((p + 1) * (p + 2) * (p + 3))

    def fourth(p):
        return 96 * math.pi / math.prod(p + k for k in range(1, 6))

    zeta = DENSITY * (GAMMA * second(s) + 2 * gamma_perp * second(2.0)) / 3
    d = KT / zeta
    eta = DENSITY * d / 2 + DENSITY ** 2 * (GAMMA * fourth(s) + 4 * gamma_perp * fourth(2.0)) / 30
    return d, eta, eta / (DENSITY * d)


def start(args, case, rate, seed):
    s, gamma_perp = case
    scene = scenes.soft_scene(num_particles=args.particles, density=DENSITY, a=A, seed=seed)
    integrator = openmmdpd.ShardlowIntegrator(openmmdpd.KT_TEMPERATURE, GAMMA, 1.0, args.dt)
    integrator.setDefaultWeightExponent(s)
    integrator.setDefaultTransverseFriction(gamma_perp)
    integrator.setRandomNumberSeed(seed)
    integrator.setShearRate(rate)
    integrator.setPressureTensorEnabled(rate != 0)
    context = openmm.Context(scene.system, integrator, openmm.Platform.getPlatformByName("CPU"),
                             {"Threads": str(args.threads)})
    context.setPositions(scene.positions)
    context.setVelocitiesToTemperature(openmmdpd.KT_TEMPERATURE, seed)
    integrator.step(round(args.equilibrate / args.dt))
    return context, integrator


def equilibrium(args, case, seed):
    """(D, its error, eta_T, its error) of one run at equilibrium: positions every FRAME for the
    MSD, the transverse currents every CURRENT."""
    context, integrator = start(args, case, 0.0, seed)
    frames, currents = [], []
    masses = np.ones(args.particles)
    length = (args.particles / DENSITY) ** (1 / 3)
    per_frame = round(FRAME / CURRENT)
    for k in range(round(args.diffusion_time / CURRENT) + 1):
        state = context.getState(getPositions=True, getVelocities=True)
        positions = state.getPositions(asNumpy=True)._value
        currents.append(dynamics.transverse_currents(positions, state.getVelocities(asNumpy=True)._value, masses, length))
        if k % per_frame == 0:
            frames.append(positions.copy())
        integrator.step(round(CURRENT / args.dt))
    times, msd, by_group = grouped_squared_displacement(np.array(frames), FRAME, 8)
    d, d_err = diffusion_with_error(times, msd, by_group)
    eta_t, eta_t_err = dynamics.transverse_viscosity(currents, CURRENT, DENSITY, length)
    return d, d_err, eta_t, eta_t_err


def viscosity(args, case, seed):
    context, integrator = start(args, case, args.rate, seed)
    blocks = []
    for _ in range(round(args.nemd_time / BLOCK)):
        integrator.resetPressureTensor()
        integrator.step(round(BLOCK / args.dt))
        blocks.append(-integrator.getAveragePressureTensor()._value[3] / args.rate)
    blocks = np.array(blocks)
    return float(blocks.mean()), standard_error(blocks)


def measure(args):
    rows = []
    for k, (s, gamma_perp) in enumerate(args.cases):
        t0 = time.perf_counter()
        d, d_err, eta_t, eta_t_err = equilibrium(args, (s, gamma_perp), seed=11 + k)
        eta, eta_err = viscosity(args, (s, gamma_perp), seed=31 + k)
        sc = eta / (DENSITY * d)
        sc_err = sc * math.hypot(eta_err / eta, d_err / d)
        d_kin, eta_kin, sc_kin = kinetic_theory(s, gamma_perp)
        rows.append(dict(s=s, gamma_perp=gamma_perp, D=d, D_err=d_err, eta=eta, eta_err=eta_err, eta_T=eta_t, eta_T_err=eta_t_err,
                         Sc=sc, Sc_err=sc_err,
                         D_kinetic=d_kin, eta_kinetic=eta_kin, Sc_kinetic=sc_kin, seconds=time.perf_counter() - t0))
        print(f"s = {s:g}, gamma_perp = {gamma_perp:g}: D = {d:.4f} +- {d_err:.4f}, eta = {eta:.3f} +- {eta_err:.3f}, "
              f"eta_T = {eta_t:.3f} +- {eta_t_err:.3f}, "
              f"Sc = {sc:.2f} +- {sc_err:.2f} "
              f"(kinetic theory {d_kin:.4f}, {eta_kin:.3f}, {sc_kin:.2f}) in {rows[-1]['seconds']:.0f} s", flush=True)
    return rows


def write(rows, args):
    os.makedirs(args.out, exist_ok=True)
    with open(os.path.join(args.out, "schmidt.csv"), "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows({k: f"{v:.6g}" for k, v in row.items()} for row in rows)
    lines = [
        "# Schmidt number against the weight exponent s and with transverse friction",
        "",
        f"Standard DPD fluid: rho {DENSITY:g}, a {A:g}, gamma {GAMMA:g}, kT {KT:g}, rc 1, N = {args.particles}, "
        f"ShardlowIntegrator S1 at dt {args.dt:g}; D and eta_T from {args.diffusion_time:g} ps at equilibrium, eta from "
        f"{args.nemd_time:g} ps of NEMD at shear rate {args.rate:g} after {args.equilibrate:g} ps.",
        "Errors are one standard error. Made by `examples/schmidt_number.py"
        + (" --quick" if args.quick else "") + "`.",
        "",
        "| s | gamma_perp | D | eta | eta_T | Sc = eta/(rho D) | D, kinetic theory | eta, kinetic theory | Sc, kinetic theory |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        lines.append(f"| {r['s']:g} | {r['gamma_perp']:g} | {r['D']:.4f} ± {r['D_err']:.4f} | {r['eta']:.3f} ± {r['eta_err']:.3f} | "
                     f"{r['eta_T']:.3f} ± {r['eta_T_err']:.3f} | "
                     f"{r['Sc']:.2f} ± {r['Sc_err']:.2f} | {r['D_kinetic']:.4f} | {r['eta_kinetic']:.3f} | {r['Sc_kinetic']:.2f} |")
    with open(os.path.join(args.out, "report.md"), "w") as f:
        f.write("\n".join(lines) + "\n")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="seconds: a small box and short runs")
    parser.add_argument("--out", default=OUT, help="output folder")
    parser.add_argument("--threads", type=int, default=2, help="CPU platform threads")
    args = parser.parse_args(argv)
    for key, value in (QUICK if args.quick else FULL).items():
        setattr(args, key, value)
    rows = measure(args)
    write(rows, args)
    return rows


if __name__ == "__main__":
    main()
