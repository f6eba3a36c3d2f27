"""openmm-dpd and LAMMPS side by side on an exported model (openmmdpd.lammps): <kT> and the
pressure of the soft DPD fluid (a 25, gamma 4.5, rc 1) from the same start and for the same
number of steps, each with its standard error (pymbar's statistical inefficiency).

The model is equilibrated on the CPU platform, exported with its positions and velocities,
then run on in LAMMPS (`lmp -in`) and in openmm-dpd. LAMMPS's thermo `temp` (3N - 3 degrees
of freedom) and `press` (kinetic plus the virial of every pair force) are sampled every
--every steps; openmm-dpd's kinetic kT over 3N - 3 and the trace of its pressure tensor
averaged over the same blocks.

    python3 -m openmmdpd.lammps_check --lmp PATH_TO_LMP [--schemes GW S1] [--density 3]
"""
import os
import subprocess
import sys
import tempfile

import numpy as np
import openmm
from openmm import unit

from . import options
from .analysis import standard_error
from .dpdplugin import DPDVVIntegrator, ShardlowIntegrator
from .lammps import export_lammps
from .pressure import pressure_tensor
from .scenes import soft_scene
from .units import KT_TEMPERATURE

SCHEMES = {"GW": DPDVVIntegrator, "S1": ShardlowIntegrator}
DURATION = ("With the defaults (N 3000, dt 0.04, 20 000 steps, GW and S1) a run takes about 5 minutes on one core "
            "(measured: 1.7 min for GW, 3.1 for S1, both programs).")


def make_integrator(scheme, dt, seed):
    integrator = SCHEMES[scheme](KT_TEMPERATURE, 4.5, 1.0, dt)
    integrator.setRandomNumberSeed(seed)
    return integrator


def thermo_rows(log_path):
    """The rows of numbers under the first `Step Temp Press` header of a LAMMPS log, as an array."""
    rows, reading = [], False
    with open(log_path) as log:
        for line in log:
            words = line.split()
            if words[:3] == ["Step", "Temp", "Press"]:
                reading = True
            elif reading and words and words[0] == "Loop":
                break
            elif reading and words:
                rows.append([float(w) for w in words])
    return np.array(rows)


def run_lammps(lmp, folder, every):
    """LAMMPS on folder/model.in with thermo every `every` steps: (temp, press) per sample after the first."""
    script = os.path.join(folder, "model.in")
    with open(script) as f:
        text = f.read().replace("thermo_style custom step temp press pe ke", "thermo_style custom step temp press")
    with open(script, "w") as f:
        f.write(text.replace("thermo 100", f"thermo {every}"))
    subprocess.run([lmp, "-in", "model.in", "-log", "log.lammps", "-screen", "none"], cwd=folder, check=True)
    rows = thermo_rows(os.path.join(folder, "log.lammps"))[1:]
    return rows[:, 1], rows[:, 2]


def run_openmm(context, integrator, steps, every, n):
    """openmm-dpd on from the exported state: (kT, pressure) per block of `every` steps."""
    integrator.setPressureTensorEnabled(True)
    kT, pressure = [], []
    for _ in range(steps // every):
        integrator.resetPressureTensor()
        integrator.step(every)
        kinetic = context.getState(getEnergy=True).getKineticEnergy().value_in_unit(unit.kilojoule_per_mole)
        kT.append(2 * kinetic / (3 * n - 3))
        pressure.append(np.mean(pressure_tensor(integrator)[:3]))
    return np.array(kT), np.array(pressure)


def compare(scheme, args):
    """One scheme: {program: (<kT>, error, <P>, error)}."""
    scene = soft_scene(num_particles=args.particles, density=args.density, a=25.0, seed=args.seed)
    integrator = make_integrator(scheme, args.dt, args.seed)
    context = openmm.Context(scene.system, integrator, openmm.Platform.getPlatformByName("CPU"), {"Threads": "1"})
    context.setPositions(scene.positions)
    context.setVelocitiesToTemperature(KT_TEMPERATURE, args.seed)
    integrator.step(args.equilibrate)
    state = context.getState(getPositions=True, getVelocities=True)
    with tempfile.TemporaryDirectory() as folder:
        export_lammps(scene.system, make_integrator(scheme, args.dt, args.seed), state, os.path.join(folder, "model"),
                      steps=args.steps)
        series = {"LAMMPS": run_lammps(args.lmp, folder, args.every)}
    series["openmm-dpd"] = run_openmm(context, integrator, args.steps, args.every, args.particles)
    return {name: (kT.mean(), standard_error(kT), p.mean(), standard_error(p)) for name, (kT, p) in series.items()}


def _parser():
    parser = options.parser("lammps_check", __doc__.split("\n\n")[0], DURATION)
    add = parser.add_argument
    add("--lmp", required=True, help="the LAMMPS executable, built with DPD-BASIC, DPD-REACT and MOLECULE")
    add("--schemes", nargs="+", default=list(SCHEMES), choices=list(SCHEMES), help="GW (fix nve) and S1 (fix shardlow)")
    add("--density", type=float, default=3.0, help="rho")
    add("-N", "--particles", type=int, default=3000, help="N")
    add("--dt", type=float, default=0.04, help="time step")
    add("--equilibrate", type=int, default=500, help="openmm-dpd steps before the export")
    add("--steps", type=int, default=20000, help="steps run by each program")
    add("--every", type=int, default=20, help="steps between samples")
    add("--seed", type=int, default=3, help="seed of the start and of both thermostats")
    return parser


def main(argv=None):
    args = _parser().parse_args(argv)
    print(f"soft fluid rho {args.density:g}, a 25, gamma 4.5, N {args.particles}, dt {args.dt:g}, {args.steps} steps")
    print(f"{'scheme':>6} {'program':>11} {'<kT>':>16} {'pressure':>18}")
    for scheme in args.schemes:
        for name, (kT, kT_err, p, p_err) in compare(scheme, args).items():
            print(f"{scheme:>6} {name:>11} {kT:>9.4f} ± {kT_err:.4f} {p:>10.3f} ± {p_err:.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
