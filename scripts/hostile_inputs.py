"""Hostile inputs: damaged checkpoints, and molecules of every bonded kind sheared for long runs.

    PYTHONPATH=build/python /usr/bin/python3 scripts/hostile_inputs.py checkpoints
    PYTHONPATH=build/python /usr/bin/python3 scripts/hostile_inputs.py shear
    PYTHONPATH=build/python /usr/bin/python3 scripts/hostile_inputs.py all --out docs/results/reliability.md

`checkpoints`: for each integrator class on the Reference and CPU platforms, 200 single-byte
flips and 200 four-byte overwrites at random offsets of a checkpoint (OpenMM's part and ours),
each loaded with `openmmdpd.load_checkpoint` in a worker process (a crash or a hang kills only
the worker: the case is counted, and the next worker goes on).  Each must be refused with a
printable message and leave the Context's positions, velocities, time and step count bit for
bit as they were.

`shear`: a fluid of molecules held together by one kind of bonded term each (harmonic and
custom bonds, compound bonds, centroid bonds, angles, torsions, CMAP) under Lees-Edwards shear
at rates 0.1 and 1 for 10^5 steps of GW and S1 on both platforms.
Every 10 steps: a molecule must have been brought back through the boundary whole (all its
particles by the same box heights), and where its term holds a distance (bonds), the distance
must stay within its thermal range.
"""
import argparse
import re
import multiprocessing as mp
import sys
import time

import numpy as np
import openmm
import openmmdpd

KT_KELVIN = openmmdpd.KT_TEMPERATURE.value_in_unit(openmm.unit.kelvin)
DT = 0.02
FLIPS = OVERWRITES = 200
CASE_TIMEOUT_S = 60


# ---------------------------------------------------------------- checkpoints

def integrator_of(name):
    """One integrator of each class, seeded."""
    kT, gamma, rc = KT_KELVIN, 4.5, 1.0
    if name == "DPDVVIntegrator":
        integrator = openmmdpd.DPDVVIntegrator(kT, gamma, rc, DT)
    elif name == "ShardlowIntegrator":
        integrator = openmmdpd.ShardlowIntegrator(kT, gamma, rc, DT)
    elif name == "LoweAndersenIntegrator":
        integrator = openmmdpd.LoweAndersenIntegrator(kT, gamma, rc, DT)
    elif name == "EDPDIntegrator":
        integrator = openmmdpd.EDPDIntegrator(kT, gamma, rc, 10.0, DT)
    elif name == "DenOtterClarkeIntegrator":
        integrator = openmmdpd.DenOtterClarkeIntegrator(kT, gamma, rc, DT)
        # Model B's averages (Nikunen et al. 2003, Table III)
        integrator.setAverageFDDotV(-4.985245)
        integrator.setAverageFDDotFD(14.507340)
        integrator.setAverageFRDotFR(9.976453)
    else:
        integrator = openmmdpd.StaggeredDPDIntegrator(kT, gamma, rc, DT, 3)
    integrator.setRandomNumberSeed(11)
    return integrator


INTEGRATOR_CLASSES = ("DPDVVIntegrator", "ShardlowIntegrator", "LoweAndersenIntegrator", "EDPDIntegrator",
                      "DenOtterClarkeIntegrator", "StaggeredDPDIntegrator")


def soft_fluid_with_chain(n=200, density=3.0, seed=3):
    """A soft fluid with a harmonic 5-bead chain in force group 1 (the staggered scheme's fast group)."""
    box = (n / density) ** (1 / 3)
    system = openmm.System()
    system.setDefaultPeriodicBoxVectors((box, 0, 0), (0, box, 0), (0, 0, box))
    rng = np.random.default_rng(seed)
    positions = rng.uniform(0, box, (n, 3))
    chain = openmm.HarmonicBondForce()
    chain.setForceGroup(1)
    chain.setUsesPeriodicBoundaryConditions(True)
    for i in range(n):
        system.addParticle(1.0)
    for i in range(1, 5):
        positions[i] = positions[i - 1] + (0.5, 0, 0)
        chain.addBond(i - 1, i, 0.5, 50.0)
    system.addForce(openmmdpd.DPDSoftRepulsionForce(25.0, 1.0))
    system.addForce(chain)
    return system, positions


def started_context(name, platform):
    system, positions = soft_fluid_with_chain()
    integrator = integrator_of(name)
    properties = {"Threads": "1"} if platform == "CPU" else {}
    context = openmm.Context(system, integrator, openmm.Platform.getPlatformByName(platform), properties)
    context.setPositions(positions)
    context.setVelocitiesToTemperature(KT_KELVIN, 5)
    integrator.step(5)
    return system, integrator, context


def snapshot(context):
    state = context.getState(getPositions=True, getVelocities=True)
    return (state.getPositions(asNumpy=True).tobytes(), state.getVelocities(asNumpy=True).tobytes(),
            state.getTime(), state.getStepCount())


def damaged_copies(checkpoint, seed):
    """(kind, offset, bytes): FLIPS single-byte flips, then OVERWRITES random 4-byte overwrites."""
    rng = np.random.default_rng(seed)
    for _ in range(FLIPS):
        data = bytearray(checkpoint)
        offset = int(rng.integers(len(data)))
        data[offset] ^= int(rng.integers(1, 256))
        yield "flip", offset, bytes(data)
    for _ in range(OVERWRITES):
        data = bytearray(checkpoint)
        offset = int(rng.integers(len(data) - 3))
        new = rng.integers(0, 256, 4, dtype=np.uint8).tobytes()
        while new == bytes(data[offset:offset + 4]):
            new = rng.integers(0, 256, 4, dtype=np.uint8).tobytes()
        data[offset:offset + 4] = new
        yield "overwrite", offset, bytes(data)


def is_readable(message):
    return bool(message) and message.isprintable() and message.isascii()


def checkpoint_worker(name, platform, seed, start, results):
    """Loads the damaged copies from number `start` on, putting one (index, outcome, detail) each."""
    system, integrator, context = started_context(name, platform)
    checkpoint = context.createCheckpoint()
    integrator.step(2)
    before = snapshot(context)
    for index, (kind, offset, data) in enumerate(damaged_copies(checkpoint, seed)):
        if index < start:
            continue
        results.put((index, "running", ""))
        try:
            openmmdpd.load_checkpoint(context, data)
            outcome, detail = "accepted", f"{kind} at {offset}"
        except openmm.OpenMMException as error:
            message = str(error)
            if not is_readable(message):
                outcome, detail = "unreadable", f"{kind} at {offset}: {message!r}"
            elif snapshot(context) != before:
                outcome, detail = "state changed", f"{kind} at {offset}: {message}"
            else:
                outcome, detail = "refused", message
        results.put((index, outcome, detail))
    results.put((None, "done", ""))


def run_checkpoint_cases(name, platform, seed):
    """Outcome counts for one class on one platform, and examples of anything not refused."""
    total = FLIPS + OVERWRITES
    counts, problems, reasons = {}, [], {}
    start = 0
    context = mp.get_context("spawn")
    while start < total:
        results = context.Queue()
        worker = context.Process(target=checkpoint_worker, args=(name, platform, seed, start, results))
        worker.start()
        current = None
        while True:
            try:
                index, outcome, detail = results.get(timeout=CASE_TIMEOUT_S)
            except Exception:  # the worker died or hangs on the case in flight
                outcome = "crash" if not worker.is_alive() else "hang"
                worker.kill()
                counts[outcome] = counts.get(outcome, 0) + 1
                problems.append(f"{outcome} at case {current}")
                start = (current if current is not None else start) + 1
                break
            if outcome == "done":
                start = total
                break
            if outcome == "running":
                current = index
                continue
            counts[outcome] = counts.get(outcome, 0) + 1
            if outcome == "refused":
                reason = re.sub(r"\d+", "N", detail.split(": ", 2)[-1].split(" (")[0])
                reasons[reason] = reasons.get(reason, 0) + 1
            else:
                problems.append(f"{outcome}: {detail}")
            start = index + 1
        worker.join(timeout=10)
    return counts, problems, reasons


def checkpoints_report():
    lines = ["## Damaged checkpoints", "",
             f"{FLIPS} single-byte flips and {OVERWRITES} four-byte overwrites at random offsets of each "
             "checkpoint, loaded with `openmmdpd.load_checkpoint` in worker processes.", "",
             "| integrator | platform | bytes | refused | accepted | state changed | unreadable | crash | hang |",
             "|---|---|---|---|---|---|---|---|---|"]
    all_reasons, all_problems = {}, []
    for k, name in enumerate(INTEGRATOR_CLASSES):
        for platform in ("Reference", "CPU"):
            started = time.time()
            _, _, context = started_context(name, platform)
            size = len(context.createCheckpoint())
            del context
            counts, problems, reasons = run_checkpoint_cases(name, platform, seed=100 + k)
            row = [counts.get(key, 0) for key in ("refused", "accepted", "state changed", "unreadable", "crash", "hang")]
            lines.append(f"| {name} | {platform} | {size} | " + " | ".join(map(str, row)) + " |")
            print(f"{name} on {platform}: {counts} in {time.time() - started:.0f} s", file=sys.stderr, flush=True)
            for reason, n in reasons.items():
                all_reasons[reason] = all_reasons.get(reason, 0) + n
            all_problems += [f"{name} on {platform}: {p}" for p in problems]
    lines += ["", "Why they were refused (all classes and platforms):", "", "| reason | cases |", "|---|---|"]
    for reason, n in sorted(all_reasons.items(), key=lambda item: -item[1]):
        lines.append(f"| {reason} | {n} |")
    if all_problems:
        lines += ["", "Not refused as they should be:", ""] + [f"- {p}" for p in all_problems[:50]]
    return lines, not all_problems


# ---------------------------------------------------------------- shear

def bonded_kinds():
    """(kind, molecule size, whether its term holds a distance, the empty Force, and a function
    adding to that Force the term that joins the molecule starting at particle o)."""
    def centroid_bond(f, o):
        first = f.addGroup([o, o + 1])
        f.addGroup([o + 2, o + 3])
        f.addBond([first, first + 1], [])

    def cmap():
        f = openmm.CMAPTorsionForce()
        f.addMap(2, [0.0, 1.0, 1.0, 0.0])
        return f

    return [
        ("HarmonicBondForce", 2, True, openmm.HarmonicBondForce, lambda f, o: f.addBond(o, o + 1, 0.5, 50.0)),
        ("CustomBondForce", 2, True, lambda: openmm.CustomBondForce("25*(r-0.5)^2"),
         lambda f, o: f.addBond(o, o + 1, [])),
        ("CustomCompoundBondForce", 2, True, lambda: openmm.CustomCompoundBondForce(2, "25*(distance(p1,p2)-0.5)^2"),
         lambda f, o: f.addBond([o, o + 1], [])),
        ("CustomCentroidBondForce", 4, False, lambda: openmm.CustomCentroidBondForce(2, "25*(distance(g1,g2)-0.5)^2"),
         centroid_bond),
        ("HarmonicAngleForce", 3, False, openmm.HarmonicAngleForce, lambda f, o: f.addAngle(o, o + 1, o + 2, 2.0, 10.0)),
        ("PeriodicTorsionForce", 4, False, openmm.PeriodicTorsionForce,
         lambda f, o: f.addTorsion(o, o + 1, o + 2, o + 3, 1, 0.0, 2.0)),
        ("CMAPTorsionForce", 5, False, cmap, lambda f, o: f.addTorsion(0, o, o + 1, o + 2, o + 3, o + 1, o + 2, o + 3, o + 4)),
    ]


def sheared_molecules(size, make_force, add_term, n=180, box=4.0, seed=7):
    """Molecules of `size` particles, joined by terms of one Force, making up half of a fluid of
    n particles, and their particle lists."""
    system = openmm.System()
    system.setDefaultPeriodicBoxVectors((box, 0, 0), (0, box, 0), (0, 0, box))
    rng = np.random.default_rng(seed)
    positions = rng.uniform(0, box, (n, 3))
    groups = []
    for i in range(n):
        system.addParticle(1.0)
    force = make_force()
    for m in range(n // 2 // size):
        o = m * size
        for k in range(1, size):
            positions[o + k] = positions[o + k - 1] + rng.normal(0, 0.3, 3)
        add_term(force, o)
        groups.append(list(range(o, o + size)))
    system.addForce(force)
    system.addForce(openmmdpd.DPDSoftRepulsionForce(25.0, 1.0))
    return system, positions, groups


def shear_run(size, make_force, add_term, integrator_name, rate, platform, steps):
    """(whether every molecule stayed whole, its largest internal distance, boundary crossings)."""
    system, positions, groups = sheared_molecules(size, make_force, add_term)
    if integrator_name == "GW":
        integrator = openmmdpd.DPDVVIntegrator(KT_KELVIN, 4.5, 1.0, DT)
    else:
        integrator = openmmdpd.ShardlowIntegrator(KT_KELVIN, 4.5, 1.0, DT)
    integrator.setShearRate(rate)
    integrator.setRandomNumberSeed(3)
    properties = {"Threads": "1"} if platform == "CPU" else {}
    context = openmm.Context(system, integrator, openmm.Platform.getPlatformByName(platform), properties)
    context.setPositions(positions)
    context.setVelocitiesToTemperature(KT_KELVIN, 9)
    members = np.array(groups)
    pairs = np.array([(g[a], g[b]) for g in groups for a in range(len(g)) for b in range(a)])
    height = system.getDefaultPeriodicBoxVectors()[1][1].value_in_unit(openmm.unit.nanometer)
    y = np.array(positions)[:, 1]
    wraps = np.zeros(len(y), dtype=int)
    whole, largest = True, 0.0
    for _ in range(steps // 10):
        integrator.step(10)
        r = context.getState(getPositions=True).getPositions(asNumpy=True).value_in_unit(openmm.unit.nanometer)
        # Flow is along x: in 10 steps a particle moves ~0.2 along y, so a jump of a box
        # height along y is the boundary bringing it back.  A molecule is whole if all its
        # particles are brought back together.
        wraps += np.rint((r[:, 1] - y) / height).astype(int)
        y = r[:, 1]
        whole &= bool(np.all(wraps[members] == wraps[members[:, :1]]))
        largest = max(largest, float(np.max(np.linalg.norm(r[pairs[:, 0]] - r[pairs[:, 1]], axis=1))))
    return whole, largest, int(np.abs(wraps[members[:, 0]]).sum())


def shear_report(steps, reference_steps):
    lines = ["## Molecules under shear", "",
             "A fluid of 180 particles (density 2.8, soft repulsion a = 25), half of them in molecules held by one "
             f"kind of bonded term each, sheared at rates 0.1 and 1 with dt = {DT}: {steps} steps on the CPU "
             f"platform, {reference_steps} on the Reference platform. Every 10 steps: whether each molecule's particles "
             "were brought back through the boundary together (whole), and the largest distance between two particles "
             "of a molecule. Bonds (spring 50 kJ/mol/nm^2, rest 0.5, kT = 1) hold it within 0.5 + 8 sigma = 1.6; "
             "angles, torsions, CMAP and centroid groups hold no distance between their particles, which the flow "
             "then draws apart (the distance is shown in brackets, for what it is).", "",
             "| bonded term | integrator | platform | rate | steps | net crossings | whole | largest distance |",
             "|---|---|---|---|---|---|---|---|"]
    all_whole = True
    for kind, size, holds, make_force, add_term in bonded_kinds():
        for integrator_name in ("GW", "S1"):
            for platform in ("Reference", "CPU"):
                for rate in (0.1, 1.0):
                    started = time.time()
                    n = steps if platform == "CPU" else reference_steps
                    whole, distance, crossings = shear_run(size, make_force, add_term, integrator_name, rate, platform, n)
                    ok = whole and (not holds or distance <= 1.6)
                    all_whole &= ok
                    shown = f"{distance:.2f}" if holds else f"({distance:.0f})"
                    lines.append(f"| {kind} | {integrator_name} | {platform} | {rate} | {n} | {crossings} | "
                                 f"{'yes' if ok else 'NO'} | {shown} |")
                    print(f"{kind} {integrator_name} {platform} rate {rate}: whole {whole}, distance {distance:.2f}, "
                          f"{crossings} crossings in {time.time() - started:.0f} s", file=sys.stderr, flush=True)
    return lines, all_whole


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    parser.add_argument("what", choices=("checkpoints", "shear", "all"))
    parser.add_argument("--steps", type=int, default=100000, help="steps of each sheared run on the CPU platform")
    parser.add_argument("--reference-steps", type=int, default=100000,
                        help="steps of each sheared run on the Reference platform (~0.5 ms a step: the whole "
                             "run with the defaults takes about 35 min on 2 cores)")
    parser.add_argument("--out", help="write the report (Markdown) here as well as to standard output")
    args = parser.parse_args()
    lines, ok = [f"Made by `scripts/hostile_inputs.py {args.what}` with openmm-dpd {openmmdpd.__version__} and "
                 f"OpenMM {openmm.Platform.getOpenMMVersion()}.", ""], True
    if args.what in ("checkpoints", "all"):
        more, passed = checkpoints_report()
        lines += more + [""]
        ok &= passed
    if args.what in ("shear", "all"):
        more, passed = shear_report(args.steps, args.reference_steps)
        lines += more + [""]
        ok &= passed
    text = "\n".join(lines)
    print(text)
    if args.out:
        with open(args.out, "w") as f:
            f.write("# Hostile inputs\n\n" + text)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
