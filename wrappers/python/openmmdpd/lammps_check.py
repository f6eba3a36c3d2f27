"""openmm-dpd and LAMMPS side by side on exported models (openmmdpd.lammps): <kT>, pressure
and g(r) of three scenes with GW (fix nve) and S1 (fix shardlow), the NEMD viscosity of model B
(GW), and LAMMPS on several OpenMP threads against one, each with its standard error.

Scenes (a 25, gamma 4.5, rc 1, N --particles): `fluid`, the standard DPD fluid at rho 3;
`model-b`, rho 4; `polymer`, the rho 3 fluid with a tenth of its beads in chains of 10 joined
by harmonic springs (k 4, rest length 0, as Groot and Warren's); `polymer-fene`, the same chains
joined by FENE springs (k 7, r_max 3, scenes.fene_bond_force), which LAMMPS reads as a table;
`lipids`, a fifth of the beads in lipids h3(t4)2 of the force field lipid-h3t4.xml in its water
(packed, relaxed and run LIPID_EQUILIBRATION steps, for the lipids to aggregate, before the
export; its cosine angles go to LAMMPS as a table too). Each model is equilibrated on
the CPU platform, exported with its positions and velocities, then run on in LAMMPS (`lmp
-in`) and in openmm-dpd for the same number of steps. LAMMPS's thermo `temp` (3N - 3 degrees of
freedom, peculiar velocities under shear) is sampled every --every steps, its pressure and P_xy
(kinetic plus the virial of every force) averaged over every step of the same blocks (`fix
ave/time`); openmm-dpd's kinetic kT over 3N - 3 likewise, and its pressure tensor averaged over
the same blocks. g(r) of frames every --frame-every steps of each program;
its difference is judged against the frames' scatter. NEMD: the model sheared at --rate
(LAMMPS `fix deform ... remap v`), eta = -<P_xy> / rate. Threads: the fluid with GW again
in LAMMPS with `-sf omp -pk omp THREADS` (the OPENMP package), whose averages must equal one
thread's within errors: other threads draw other random numbers, so only averages can agree.

    python3 -m openmmdpd.lammps_check --lmp PATH_TO_LMP [--scenes fluid model-b polymer] [--out FILE.md]
"""
import os
import subprocess
import sys
import tempfile

import numpy as np
import openmm
from openmm import app, unit

from . import forcefield, options, packer
from .analysis import frame_radial_distributions, standard_error
from .dpdplugin import DPDVVIntegrator, ShardlowIntegrator
from .lammps import export_lammps
from .pressure import PARTS, pressure_tensor
from .scenes import fene_bond_force, harmonic_bond_force, random_walk, soft_scene
from .shear import impose_flow, remove_net_momentum
from .units import KT_TEMPERATURE

SCHEMES = {"GW": DPDVVIntegrator, "S1": ShardlowIntegrator}
# Whether LAMMPS's pressure holds the thermostat's virial: pair dpd computes the dissipative and
# random forces with the conservative ones; fix shardlow updates velocities and adds no virial
# (pair dpd/fdt computes only the conservative force), so S1 is compared without that part.
LAMMPS_COUNTS_THERMOSTAT = {"GW": True, "S1": False}
DENSITY = {"fluid": 3.0, "model-b": 4.0, "polymer": 3.0, "polymer-fene": 3.0, "lipids": 3.0}
DEFAULT_SCENES = ["fluid", "model-b", "polymer"]
CHAIN_LENGTH, CHAIN_FRACTION, BOND_K = 10, 0.1, 4.0
LIPID_FRACTION = 0.2
LIPID_EQUILIBRATION = 20000  # steps: the lipids aggregate from the packed start; sampling a drift would not do
THERMOSTAT_PART = PARTS.index("thermostat")
G_R_MAX, G_R_BINS = 2.0, 80
DURATION = ("With the defaults (N 3000, dt 0.04, 20 000 steps, three scenes with GW and S1, NEMD and the threads "
            "check) a run takes about 25 minutes on 2 cores; polymer-fene and lipids together add about 15.")


# --- the models --------------------------------------------------------------------------------

def lipid_model(args):
    """(System, positions in nm) of lipids in water from lipid-h3t4.xml, packed (not yet relaxed).
    Its thermostat table is friction 4.5 and cutoff 1 for every pair, make_integrator's."""
    field = app.ForceField(forcefield.data_path("lipid-h3t4.xml"))
    lipids = int(args.particles * LIPID_FRACTION) // forcefield.LIPID_H3T4.num_beads
    water = args.particles - lipids * forcefield.LIPID_H3T4.num_beads
    topology, positions = packer.pack([(forcefield.LIPID_H3T4, lipids), (packer.Molecule.single("w", ["w"]), water)],
                                      density=DENSITY["lipids"], bond_length=0.7, seed=args.seed)
    return field.createSystem(topology, removeCMMotion=False), np.array(positions.value_in_unit(unit.nanometer))


def build_model(scene, args):
    """(System, positions in nm) of a scene: the soft fluid, with chains on `polymer` and `polymer-fene`."""
    if scene == "lipids":
        return lipid_model(args)
    built = soft_scene(num_particles=args.particles, density=DENSITY[scene], a=25.0, seed=args.seed)
    positions = built.positions.value_in_unit(unit.nanometer)
    if scene.startswith("polymer"):
        rng = np.random.default_rng(args.seed)
        length = built.system.getDefaultPeriodicBoxVectors()[0][0].value_in_unit(unit.nanometer)
        chains = int(args.particles * CHAIN_FRACTION) // CHAIN_LENGTH
        for c in range(chains):
            start = rng.uniform(0, length, 3)
            positions[c * CHAIN_LENGTH:(c + 1) * CHAIN_LENGTH] = random_walk(rng, CHAIN_LENGTH, start, length,
                                                                               min_distance=0.0)
        bonds = [(c * CHAIN_LENGTH + k, c * CHAIN_LENGTH + k + 1) for c in range(chains)
                 for k in range(CHAIN_LENGTH - 1)]
        springs = fene_bond_force(bonds) if scene == "polymer-fene" else harmonic_bond_force(bonds, k=BOND_K)
        built.system.addForce(springs)
    return built.system, positions


def make_integrator(scheme, dt, seed, rate=0.0):
    integrator = SCHEMES[scheme](KT_TEMPERATURE, 4.5, 1.0, dt)
    integrator.setRandomNumberSeed(seed)
    integrator.setShearRate(rate)
    return integrator


def equilibrated(scene, scheme, args, rate=0.0):
    """(System, integrator, Context) after args.equilibrate steps from the scene's start, the flow
    imposed at `rate`, the pressure tensor on."""
    system, positions = build_model(scene, args)
    integrator = make_integrator(scheme, args.dt, args.seed, rate)
    integrator.setPressureTensorEnabled(True)
    context = openmm.Context(system, integrator, openmm.Platform.getPlatformByName("CPU"), {"Threads": "1"})
    context.setPositions(positions)
    if scene == "lipids":
        packer.relax(context)  # a packed start overlaps beads that repel at a = 75
    context.setVelocitiesToTemperature(KT_TEMPERATURE, args.seed)
    remove_net_momentum(context)  # under shear LAMMPS counts its drift as heat (compute temp/deform)
    impose_flow(context, rate)
    integrator.step(max(args.equilibrate, LIPID_EQUILIBRATION) if scene == "lipids" else args.equilibrate)
    return system, integrator, context


# --- LAMMPS ------------------------------------------------------------------------------------

def thermo_rows(log_path):
    """The rows of numbers under the first `Step Temp ...` header of a LAMMPS log, as an array."""
    rows, reading = [], False
    with open(log_path) as log:
        for line in log:
            words = line.split()
            if words[:2] == ["Step", "Temp"]:
                reading = True
            elif reading and words and words[0] == "Loop":
                break
            elif reading and words:
                rows.append([float(w) for w in words])
    return np.array(rows)


def dump_frames(path):
    """The positions of every frame of a LAMMPS `dump custom ... id x y z` file sorted by id: (frames, N, 3)."""
    frames = []
    with open(path) as dump:
        lines = dump.read().split("\n")
    k = 0
    while k < len(lines):
        if lines[k].startswith("ITEM: NUMBER OF ATOMS"):
            n = int(lines[k + 1])
        elif lines[k].startswith("ITEM: ATOMS"):
            rows = np.array([[float(w) for w in line.split()] for line in lines[k + 1:k + 1 + n]])
            frames.append(rows[np.argsort(rows[:, 0]), 1:4])
            k += n
        k += 1
    return np.array(frames)


def _edit_script(folder, every, frame_every, threads):
    """The exported script sampling temp every `every` steps with press and pxy averaged over those
    steps, and dumping frames."""
    script = os.path.join(folder, "model.in")
    with open(script) as f:
        text = f.read().replace("thermo_style custom step temp press pe ke",
                                f"fix averages all ave/time 1 {every} {every} c_thermo_press c_thermo_press[4]\n"
                                "thermo_style custom step temp f_averages[1] f_averages[2]")
    text = text.replace("thermo 100", f"thermo {every}")
    if frame_every:
        text = text.replace("\nrun ", f"\ndump frames all custom {frame_every} frames.dump id x y z\nrun ")
    with open(script, "w") as f:
        f.write(text)
    return ["-sf", "omp", "-pk", "omp", str(threads)] if threads > 1 else []


def run_lammps(lmp, folder, every, frame_every=0, threads=1):
    """LAMMPS on folder/model.in: ((temp, press, pxy) per sample after the first, frames or None)."""
    accelerate = _edit_script(folder, every, frame_every, threads)
    environment = dict(os.environ, OMP_NUM_THREADS=str(threads))
    subprocess.run([lmp, *accelerate, "-in", "model.in", "-log", "log.lammps", "-screen", "none"], cwd=folder,
                   check=True, env=environment)
    rows = thermo_rows(os.path.join(folder, "log.lammps"))[1:]
    frames = dump_frames(os.path.join(folder, "frames.dump"))[1:] if frame_every else None
    return (rows[:, 1], rows[:, 2], rows[:, 3]), frames


def run_lammps_export(system, scheme, rate, context, args, frame_every=0, threads=1):
    """LAMMPS run on from the state of `context`, exported with a new integrator of the same scheme (run_lammps)."""
    state = context.getState(getPositions=True, getVelocities=True)
    with tempfile.TemporaryDirectory() as folder:
        export_lammps(system, make_integrator(scheme, args.dt, args.seed, rate), state, os.path.join(folder, "model"),
                      steps=args.steps)
        return run_lammps(args.lmp, folder, args.every, frame_every, threads)


# --- openmm-dpd --------------------------------------------------------------------------------

def run_openmm(context, integrator, args, frame_every=0, thermostat=True):
    """openmm-dpd on from the exported state: ((kT, pressure, P_xy) per block of `every` steps, frames);
    thermostat=False leaves the thermostat's part out of the pressure, as LAMMPS's fix shardlow does."""
    n = context.getSystem().getNumParticles()
    series, frames = [], []
    for block in range(args.steps // args.every):
        integrator.resetPressureTensor()
        integrator.step(args.every)
        kinetic = context.getState(getEnergy=True).getKineticEnergy().value_in_unit(unit.kilojoule_per_mole)
        tensor = pressure_tensor(integrator) - (0 if thermostat else pressure_tensor(integrator, THERMOSTAT_PART))
        series.append((2 * kinetic / (3 * n - 3), np.mean(tensor[:3]), tensor[3]))
        if frame_every and ((block + 1) * args.every) % frame_every == 0:
            frames.append(context.getState(getPositions=True).getPositions(asNumpy=True).value_in_unit(unit.nanometer))
    return tuple(np.array(series).T), (np.array(frames) if frame_every else None)


# --- the comparisons ---------------------------------------------------------------------------

def _mean(series):
    return float(np.mean(series)), standard_error(series)


def g_of_r(frames, box_length):
    """(r, mean g, its standard error per bin from the scatter of the frames' g)."""
    r, g = frame_radial_distributions(frames, box_length, min(G_R_MAX, box_length / 2), G_R_BINS)
    return r, g.mean(axis=0), g.std(axis=0, ddof=1) / np.sqrt(len(g))


def g_difference(lammps_frames, openmm_frames, box_length):
    """(largest |g_LAMMPS - g_openmm-dpd|, chi^2 per bin of the difference in its noise) over r > 0.1."""
    r, g1, e1 = g_of_r(lammps_frames, box_length)
    _, g2, e2 = g_of_r(openmm_frames, box_length)
    keep = (r > 0.1) & ((e1 > 0) | (e2 > 0))
    difference = (g1 - g2)[keep]
    return float(np.abs(difference).max()), float(np.mean(difference ** 2 / (e1[keep] ** 2 + e2[keep] ** 2)))


def compare_scene(scene, scheme, args):
    """{program: {kT, P (value, error)}}, g(r) difference: one scene and scheme at equilibrium."""
    system, integrator, context = equilibrated(scene, scheme, args)
    box = system.getDefaultPeriodicBoxVectors()[0][0].value_in_unit(unit.nanometer)
    (kT, p, _), lammps_frames = run_lammps_export(system, scheme, 0.0, context, args, args.frame_every)
    (kT2, p2, _), openmm_frames = run_openmm(context, integrator, args, args.frame_every,
                                             LAMMPS_COUNTS_THERMOSTAT[scheme])
    results = {"LAMMPS": dict(kT=_mean(kT), P=_mean(p)), "openmm-dpd": dict(kT=_mean(kT2), P=_mean(p2))}
    return results, g_difference(lammps_frames, openmm_frames, box)


def compare_viscosity(args):
    """{program: eta (value, error)}: model B sheared at args.rate with GW."""
    system, integrator, context = equilibrated("model-b", "GW", args, args.rate)
    (_, _, pxy), _ = run_lammps_export(system, "GW", args.rate, context, args)
    (_, _, pxy2), _ = run_openmm(context, integrator, args)
    return {name: (-np.mean(s) / args.rate, standard_error(s) / args.rate)
            for name, s in (("LAMMPS", pxy), ("openmm-dpd", pxy2))}


def compare_threads(args):
    """{threads: {kT, P}}: the fluid with GW in LAMMPS on 1 and args.threads OpenMP threads."""
    system, _, context = equilibrated("fluid", "GW", args)
    found = {}
    for threads in (1, args.threads):
        (kT, p, _), _ = run_lammps_export(system, "GW", 0.0, context, args, threads=threads)
        found[threads] = dict(kT=_mean(kT), P=_mean(p))
    return found


# --- the report --------------------------------------------------------------------------------

def _pm(value):
    return f"{value[0]:.4f} ± {value[1]:.4f}"


def _sigmas(a, b):
    return abs(a[0] - b[0]) / np.hypot(a[1], b[1])


def _scene_lines(scene, scheme, results, g):
    cells = [scene, scheme]
    for key in ("kT", "P"):
        lammps, ours = results["LAMMPS"][key], results["openmm-dpd"][key]
        cells += [_pm(lammps), _pm(ours), f"{_sigmas(lammps, ours):.1f}"]
    return ["| " + " | ".join(cells + [f"{g[0]:.4f}", f"{g[1]:.2f}"]) + " |"]


def report(args):
    lipids = f" ({max(args.equilibrate, LIPID_EQUILIBRATION)} for the lipids)" if "lipids" in args.scenes else ""
    lines = [f"N {args.particles}, a 25, gamma 4.5, rc 1, dt {args.dt:g}, {args.steps} steps per program after "
             f"{args.equilibrate}{lipids} in openmm-dpd; samples every {args.every} steps, g(r) frames every "
             f"{args.frame_every}; seed {args.seed}.", "",
             "The pressures are those LAMMPS counts: with the thermostat's virial for GW (pair dpd), without it for "
             "S1 (fix shardlow adds none), openmm-dpd's likewise.", "",
             "| scene | scheme | <kT> LAMMPS | <kT> openmm-dpd | sigmas | P LAMMPS | P openmm-dpd | sigmas | "
             "max abs(g diff) | chi^2/bin of g diff |", "|---" * 10 + "|"]
    for scene in args.scenes:
        for scheme in args.schemes:
            lines += _scene_lines(scene, scheme, *compare_scene(scene, scheme, args))
            print(lines[-1], flush=True)
    if args.rate > 0:
        eta = compare_viscosity(args)
        lines += ["", f"NEMD, model B, GW, rate {args.rate:g}: eta LAMMPS {_pm(eta['LAMMPS'])}, openmm-dpd "
                      f"{_pm(eta['openmm-dpd'])} ({_sigmas(eta['LAMMPS'], eta['openmm-dpd']):.1f} sigmas)."]
        print(lines[-1], flush=True)
    if args.threads > 1:
        found = compare_threads(args)
        one, many = found[1], found[args.threads]
        lines += ["", f"LAMMPS on 1 and {args.threads} OpenMP threads, fluid, GW: <kT> {_pm(one['kT'])} and "
                      f"{_pm(many['kT'])} ({_sigmas(one['kT'], many['kT']):.1f} sigmas), P {_pm(one['P'])} and "
                      f"{_pm(many['P'])} ({_sigmas(one['P'], many['P']):.1f} sigmas)."]
        print(lines[-1], flush=True)
    return lines


def _parser():
    parser = options.parser("lammps_check", __doc__.split("\n\n")[0], DURATION)
    add = parser.add_argument
    add("--lmp", required=True, help="the LAMMPS executable, built with DPD-BASIC, DPD-REACT, MOLECULE (and OPENMP "
                                     "for --threads)")
    add("--scenes", nargs="+", default=DEFAULT_SCENES, choices=list(DENSITY), help="the models compared")
    add("--schemes", nargs="+", default=list(SCHEMES), choices=list(SCHEMES), help="GW (fix nve) and S1 (fix shardlow)")
    add("-N", "--particles", type=int, default=3000, help="N")
    add("--dt", type=float, default=0.04, help="time step")
    add("--equilibrate", type=int, default=500, help="openmm-dpd steps before the export")
    add("--steps", type=int, default=20000, help="steps run by each program")
    add("--every", type=int, default=20, help="steps between samples")
    add("--frame-every", type=int, default=250, help="steps between g(r) frames")
    add("--rate", type=float, default=0.2, help="shear rate of model B's NEMD run (0: none)")
    add("--threads", type=int, default=2, help="OpenMP threads of the second LAMMPS run of the fluid (1: none)")
    add("--seed", type=int, default=3, help="seed of the start and of both thermostats")
    add("--out", help="also write the table to this Markdown file")
    return parser


def _command(given):
    """The command that made the table, without the path of LAMMPS (scripts/lammps-check.sh finds its own)."""
    kept, skip = [], False
    for word in given:
        if not skip and word != "--lmp" and not word.startswith("--lmp="):
            kept.append(word)
        skip = word == "--lmp"
    return " ".join(["bash scripts/lammps-check.sh"] + kept)


def main(argv=None):
    args = _parser().parse_args(argv)
    lines = report(args)
    if args.out:
        command = _command(argv if argv is not None else sys.argv[1:])
        with open(args.out, "w") as f:
            f.write("\n".join([f"`{command}`", ""] + lines) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
