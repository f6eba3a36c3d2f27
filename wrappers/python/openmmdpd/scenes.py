"""The standard DPD scenes (docs/guide/scenes.md), built from OpenMM's own Forces.

Everything is in reduced units (rc = 1 nm, m = 1 amu, kT = 1 kJ/mol; see units.py).
A scene carries no thermostat: the integrator supplies the dissipative and random forces.
"""
from collections import namedtuple

import numpy as np
import openmm
from openmm import app, unit

__all__ = ["Scene", "SCENES", "build_scene", "ideal_scene", "soft_scene", "polymer_scene", "fene_chains_scene",
           "wlc_shear_scene", "FAST_FORCE_GROUP", "WLC_LP_RATIO", "LAMBDA_DNA", "underhill_doyle_ratio",
           "fractional_extension", "update_persistence_ratio",
           "soft_repulsion_force", "harmonic_bond_force", "wca_force", "fene_bond_force",
           "wlc_bond_force", "periodic_marker_force", "random_positions", "random_walk"]

Scene = namedtuple("Scene", "topology system positions name chain_particles")
Scene.__doc__ = """A ready-to-simulate system.

chain_particles: tuple of chains, each a tuple of particle indices in bond order
(empty for scenes without chains)."""

#: The names of the scenes build_scene() builds.
SCENES = ("ideal", "soft", "polymer", "fene-chains", "wlc-shear")

#: The force group of the stiff polymer forces (FENE, WCA) in the scenes made for the
#: staggered integrator; StaggeredDPDIntegrator's default fastForceGroups is this group.
FAST_FORCE_GROUP = 1


def soft_repulsion_force(num_particles, a, types=None, cutoff=1.0, native=True):
    """Groot–Warren soft repulsion, energy a_ij*rc*(1 - r/rc)^2/2 with rc = cutoff.

    a: a number (one type) or a symmetric n x n matrix of a_ij (kJ/mol/nm);
    types: per-particle type indices into that matrix (default: all type 0).
    native: this plugin's DPDSoftRepulsionForce (fast); False gives the same interaction
    as OpenMM's CustomNonbondedForce, for comparison or for users without the plugin.
    """
    table = np.atleast_2d(np.asarray(a, dtype=float))
    ntypes = table.shape[0]
    if table.shape != (ntypes, ntypes) or not np.allclose(table, table.T):
        raise ValueError(f"a must be a number or a symmetric square matrix, "
                         f"got shape {table.shape}")
    types = np.zeros(num_particles, dtype=int) if types is None else np.asarray(types, dtype=int)
    if types.shape != (num_particles,) or types.min() < 0 or types.max() >= ntypes:
        raise ValueError(f"types must be {num_particles} indices in [0, {ntypes})")
    if native:
        return _native_soft_repulsion(table, types, cutoff)
    force = openmm.CustomNonbondedForce(f"0.5*aij(type1, type2)*rc*(1 - r/rc)^2; rc={cutoff!r}")
    force.setName("SoftRepulsion")
    # Discrete2DFunction is indexed i + n*j; the table is symmetric so the order is moot.
    force.addTabulatedFunction("aij", openmm.Discrete2DFunction(ntypes, ntypes,
                                                                table.ravel().tolist()))
    force.addPerParticleParameter("type")
    for t in types:
        force.addParticle([float(t)])
    force.setNonbondedMethod(openmm.CustomNonbondedForce.CutoffPeriodic)
    force.setCutoffDistance(cutoff)
    return force


def _native_soft_repulsion(table, types, cutoff):
    from . import DPDSoftRepulsionForce  # the C++ extension
    force = DPDSoftRepulsionForce(float(table[0, 0]), cutoff)
    force.setName("SoftRepulsion")
    for i, t in enumerate(types):
        if t != 0:
            force.setParticleType(i, int(t))
    used = sorted(set(types.tolist()))
    for k, t1 in enumerate(used):
        for t2 in used[k:]:
            if (t1, t2) != (0, 0):
                force.addTypePair(t1, t2, float(table[t1, t2]), cutoff)
    return force


def harmonic_bond_force(bonds, k=7.0, length=0.0):
    """Harmonic springs k/2 (r - length)^2 (Nikunen et al. 2003: k = 7, rest length 0)."""
    force = openmm.HarmonicBondForce()
    force.setName("HarmonicBond")
    for i, j in bonds:
        force.addBond(i, j, length, k)
    force.setUsesPeriodicBoundaryConditions(True)
    return force


def wca_force(num_particles, particles, bonds=(), epsilon=1.0):
    """Truncated-shifted LJ 4 eps [(l/r)^12 - (l/r)^6 + 1/4], l = 2^(-1/6), cutoff 1.

    Acts only between `particles` (the chain beads); directly bonded pairs are excluded.
    """
    force = openmm.CustomNonbondedForce(
        f"4*eps*((l/r)^12 - (l/r)^6 + 0.25); eps={epsilon!r}; l={2 ** (-1 / 6)!r}")
    force.setName("WCA")
    for _ in range(num_particles):
        force.addParticle([])
    force.addInteractionGroup(particles, particles)
    force.createExclusionsFromBonds([tuple(b) for b in bonds], 1)
    force.setNonbondedMethod(openmm.CustomNonbondedForce.CutoffPeriodic)
    force.setCutoffDistance(1.0)
    return force


def fene_bond_force(bonds, k=7.0, rmax=3.0):
    """FENE springs -k/2 rmax^2 ln(1 - r^2/rmax^2) (Symeonidis and Karniadakis 2006: k = 7, rmax = 3).

    Written with log(sqrt(...)) so that r >= rmax gives NaN energy and forces, which an
    integrator can detect, rather than the finite wrong force of ln|1 - r^2/rmax^2|.
    """
    force = openmm.CustomBondForce(f"-k*rmax^2*log(sqrt(1 - (r/rmax)^2)); k={k!r}; rmax={rmax!r}")
    force.setName("FENE")
    for i, j in bonds:
        force.addBond(i, j, [])
    force.setUsesPeriodicBoundaryConditions(True)
    return force


#: The global parameter of wlc_bond_force(..., lp_ratio=True): effective over true persistence length.
WLC_LP_RATIO = "lpRatio"


def wlc_bond_force(bonds, lp, l_spring, kT=1.0, periodic=True, lp_ratio=False):
    """Marko–Siggia worm-like springs, F(r) = kT/lp [1/(4(1-R)^2) - 1/4 + R], R = r/l_spring.

    Energy (zero at r = 0): kT/lp l_spring [1/(4(1-R)) - 1/4 - R/4 + R^2/2].
    1/(1-R) is written exp(-log(1-R)) so that R > 1 gives NaN energy and forces, as for
    FENE; Lepton simplifies the sqrt forms (sqrt(x)^2, x - x) away.
    periodic=False measures bonds directly (for springs longer than half the box: the
    integrators keep molecules whole). lp_ratio=True makes the persistence length
    lp * WLC_LP_RATIO, a global parameter (default 1) for a correction that changes in a run.
    """
    persistence = f"(lp*{WLC_LP_RATIO})" if lp_ratio else "lp"
    force = openmm.CustomBondForce(
        f"kT/{persistence}*L*(0.25*exp(-log(1 - R)) - 0.25 - 0.25*R + 0.5*R^2); R=r/L; "
        f"kT={kT!r}; lp={lp!r}; L={l_spring!r}")
    force.setName("WormLikeChain")
    if lp_ratio:
        force.addGlobalParameter(WLC_LP_RATIO, 1.0)
    for i, j in bonds:
        force.addBond(i, j, [])
    force.setUsesPeriodicBoundaryConditions(periodic)
    return force


def periodic_marker_force():
    """An empty force that makes System.usesPeriodicBoundaryConditions() true at no cost.

    Integrators decide periodicity from the System, and a scene without conservative
    forces would otherwise report a non-periodic one.
    """
    force = openmm.CustomBondForce("0")
    force.setName("PeriodicMarker")
    force.setUsesPeriodicBoundaryConditions(True)
    return force


def random_positions(rng, num_particles, box_length):
    """Uniform positions in the cubic box [0, L)^3, an (n, 3) array in nm."""
    return rng.uniform(0.0, box_length, size=(num_particles, 3))


def random_walk(rng, num_beads, start, box_length, bond_length=0.5, min_distance=0.9, avoid=None):
    """A chain as a random walk of fixed step length from `start` (unwrapped), (n, 3) in nm.

    Steps that bring a bead closer than min_distance (minimum image) to any bead but its
    predecessor are redrawn: the WCA energy of a random walk's overlaps would blow up the
    first steps, while at 0.9 it is below 1 kT. `avoid`: other beads ((m, 3), e.g. earlier
    chains) to keep as far away.
    """
    avoid = np.zeros((0, 3)) if avoid is None else np.asarray(avoid, dtype=float).reshape(-1, 3)
    beads = [np.asarray(start, dtype=float)]
    for _ in range(num_beads - 1):
        for _attempt in range(1000):
            step = rng.normal(size=3)
            candidate = beads[-1] + bond_length * step / np.linalg.norm(step)
            d = candidate - np.vstack([np.array(beads[:-1]).reshape(-1, 3), avoid])
            d -= box_length * np.round(d / box_length)
            if np.all(np.sum(d * d, axis=1) >= min_distance ** 2):
                break
        else:
            raise RuntimeError(f"random walk stuck after {len(beads)} beads; "
                               "lower min_distance or raise bond_length")
        beads.append(candidate)
    return np.array(beads)


def _box_length(num_particles, density):
    return (num_particles / density) ** (1 / 3)


def _make_scene(name, num_particles, density, positions, chains, box_lengths=None):
    """System with unit masses in a cubic box (or one of box_lengths (Lx, Ly, Lz)), and its
    Topology (one residue per bead).

    The chains must be the leading particles, in order, so that Topology atom indices
    equal particle indices.
    """
    flat = [i for chain in chains for i in chain]
    if flat != list(range(len(flat))):
        raise ValueError("chain particles must come first and in order")
    if box_lengths is None:
        box_lengths = (_box_length(num_particles, density),) * 3
    system = openmm.System()
    for _ in range(num_particles):
        system.addParticle(1.0)
    box = [openmm.Vec3(box_lengths[0], 0, 0), openmm.Vec3(0, box_lengths[1], 0),
           openmm.Vec3(0, 0, box_lengths[2])]
    system.setDefaultPeriodicBoxVectors(*box)

    topology = app.Topology()
    topology.setPeriodicBoxVectors(box * unit.nanometer)
    for chain in chains:
        top_chain = topology.addChain()
        beads = [topology.addAtom("B", None, topology.addResidue("MON", top_chain))
                 for _ in chain]
        for bead1, bead2 in zip(beads[:-1], beads[1:]):
            topology.addBond(bead1, bead2)
    solvent = topology.addChain()
    for _ in range(num_particles - len(flat)):
        topology.addAtom("S", None, topology.addResidue("SOL", solvent))
    return Scene(topology, system, positions * unit.nanometer, name,
                 tuple(tuple(chain) for chain in chains))


def ideal_scene(num_particles=4000, density=4.0, seed=1):
    """Model A: no conservative force (Nikunen et al. 2003, §II.C.1)."""
    rng = np.random.default_rng(seed)
    positions = random_positions(rng, num_particles, _box_length(num_particles, density))
    scene = _make_scene("ideal", num_particles, density, positions, ())
    scene.system.addForce(periodic_marker_force())
    return scene


def soft_scene(num_particles=4000, density=4.0, a=25.0, seed=1, soft_repulsion_types=None, native_force=True):
    """Model B: soft repulsion a (Nikunen et al. 2003, §II.C.2).

    a may be an n x n a_ij matrix, with soft_repulsion_types the per-particle type indices.
    native_force=False builds the repulsion as a CustomNonbondedForce instead.
    """
    rng = np.random.default_rng(seed)
    positions = random_positions(rng, num_particles, _box_length(num_particles, density))
    scene = _make_scene("soft", num_particles, density, positions, ())
    scene.system.addForce(soft_repulsion_force(num_particles, a, soft_repulsion_types, native=native_force))
    return scene


def polymer_scene(num_particles=4000, density=4.0, chain_length=20, a=0.0, seed=1,
                  soft_repulsion_types=None, native_force=True):
    """Ideal solvent plus one chain (Nikunen et al. 2003, §II.C.3): harmonic bonds k = 7, rest length 0,
    WCA between beads. Particles 0..chain_length-1 are the chain.

    a = 0 (the paper's case) adds no soft repulsion; otherwise it is added to all particles
    as in soft_scene. An a_ij matrix without soft_repulsion_types makes the solvent type 0
    and the chain beads type 1.
    """
    rng = np.random.default_rng(seed)
    box_length = _box_length(num_particles, density)
    chain = list(range(chain_length))
    positions = np.vstack([
        random_walk(rng, chain_length, rng.uniform(0, box_length, 3), box_length),
        random_positions(rng, num_particles - chain_length, box_length)])
    scene = _make_scene("polymer", num_particles, density, positions, (chain,))
    bonds = list(zip(chain[:-1], chain[1:]))
    system = scene.system
    system.addForce(harmonic_bond_force(bonds))
    system.addForce(wca_force(num_particles, chain, bonds))
    if np.any(np.asarray(a) != 0):
        if soft_repulsion_types is None and np.ndim(a) == 2:
            soft_repulsion_types = [1] * chain_length + [0] * (num_particles - chain_length)
        system.addForce(soft_repulsion_force(num_particles, a, soft_repulsion_types, native=native_force))
    return scene


def fene_chains_scene(chain_length=20, num_chains=4, num_particles=4000, density=4.0, a=18.75, seed=1,
                      native_force=True):
    """Polymers in a soft DPD solvent (Symeonidis and Karniadakis 2006, §5.1): num_chains chains
    of chain_length beads, FENE bonds k = 7, rmax = 3, WCA between all beads (bonded pairs included), soft
    repulsion a = 75 kT/rho = 18.75 between all particles. Particles 0..num_chains*chain_length-1
    are the chains, chain c being c*chain_length .. (c+1)*chain_length-1.

    The stiff forces, FENE and WCA, are in force group FAST_FORCE_GROUP (1); the soft
    repulsion is in group 0. This is what StaggeredDPDIntegrator expects by default: it
    sub-cycles the fast group and takes the chain beads as the particles that group acts on.
    FENE past rmax gives NaN forces, which the integrators report as an error naming the step.
    """
    if chain_length < 2 or num_chains < 1 or num_chains * chain_length > num_particles:
        raise ValueError("need chain_length >= 2, num_chains >= 1 and room for the chains")
    rng = np.random.default_rng(seed)
    box_length = _box_length(num_particles, density)
    chains = [list(range(c * chain_length, (c + 1) * chain_length)) for c in range(num_chains)]
    walks = []
    for _ in chains:
        avoid = np.vstack(walks) if walks else None
        for _attempt in range(100):
            start = rng.uniform(0, box_length, 3)
            if avoid is not None:
                d = start - avoid
                d -= box_length * np.round(d / box_length)
                if np.min(np.sum(d * d, axis=1)) < 0.9 ** 2:
                    continue
            # FENE bonds relax near 0.97; WCA (cutoff 1) makes closer contacts costly
            try:
                walks.append(random_walk(rng, chain_length, start, box_length,
                                         bond_length=0.97, min_distance=0.9, avoid=avoid))
                break
            except RuntimeError:
                continue
        else:
            raise RuntimeError("could not place the chains apart; use fewer or shorter chains")
    num_beads = num_chains * chain_length
    positions = np.vstack(walks + [random_positions(rng, num_particles - num_beads, box_length)])
    scene = _make_scene("fene-chains", num_particles, density, positions, chains)
    bonds = [(i, j) for chain in chains for i, j in zip(chain[:-1], chain[1:])]
    system = scene.system
    beads = list(range(num_beads))
    # WCA acts between all bead pairs, bonded ones included (as in Kremer-Grest chains):
    # with FENE k = 7, rmax = 3 the bonds then sit near 0.97 and 5-bead chains have
    # <Rg> ~ 1, as in Symeonidis and Karniadakis 2006, Table 4.
    for fast in (fene_bond_force(bonds), wca_force(num_particles, beads)):
        fast.setForceGroup(FAST_FORCE_GROUP)
        system.addForce(fast)
    system.addForce(soft_repulsion_force(num_particles, a, native=native_force))
    return scene


#: lambda-phage DNA as Symeonidis and Karniadakis 2006, §3, model it (after Underhill and Doyle):
#: contour length and persistence length in micrometres.
LAMBDA_DNA = {"contour_length": 21.1, "persistence_length": 0.053}


def underhill_doyle_ratio(extension, num_beads):
    """Symeonidis and Karniadakis' (2006, §3) linear fit to Underhill and Doyle's correction for
    M-bead Marko–Siggia chains: lp_effective / lp_true = (1 - z) c (M - 1) + 1, c = 0.022 (M <= 20) or 0.025,
    z in [0, 1] the fractional extension of the whole molecule (1 for a dumbbell, M = 2:
    no correction)."""
    if num_beads <= 2:
        return 1.0
    z = min(max(float(extension), 0.0), 1.0)
    return (1.0 - z) * (0.022 if num_beads <= 20 else 0.025) * (num_beads - 1) + 1.0


def fractional_extension(chain_positions, contour_length, axis=0):
    """The chain's largest extent along `axis` (max - min of its beads, unwrapped as the
    integrators keep molecules), over its contour length: the <x>/L per frame of Symeonidis and
    Karniadakis 2006, §8."""
    x = np.asarray(chain_positions, dtype=float)[:, axis]
    return float((x.max() - x.min()) / contour_length)


def update_persistence_ratio(context, chain_positions, contour_length, axis=0):
    """Set the WLC force's WLC_LP_RATIO from the chain's current extension (Underhill–Doyle).

    Symeonidis and Karniadakis apply the correction at every step; calling this every few steps applies it
    with that lag. Returns the ratio set."""
    ratio = underhill_doyle_ratio(fractional_extension(chain_positions, contour_length, axis), len(chain_positions))
    context.setParameter(WLC_LP_RATIO, ratio)
    return ratio


def wlc_shear_scene(num_particles=4000, box=(10.0, 20.0, 5.0), a=18.75, num_beads=5, l_spring=8.0, seed=1,
                    native_force=True):
    """One worm-like chain (λ-phage DNA) in a soft DPD solvent, for Lees–Edwards shear along x
    with its gradient along y (Symeonidis and Karniadakis 2006, §8): num_particles in a box
    Lx x Ly x Lz (4000 in 10 x 20 x 5, density 4), soft repulsion a = 75 kT/rho = 18.75 between all particles
    (solvent–solvent, bead–solvent and bead–bead: Symeonidis and Karniadakis model beads and
    solvent alike but for the springs; no LJ between beads), the thermostat (the integrator's) on all pairs.
    Particles 0..num_beads-1 are the chain.

    The chain: num_beads beads joined by Marko–Siggia springs (wlc_bond_force) in force group
    FAST_FORCE_GROUP, not periodic (a spring may be longer than half the box; the
    integrators wrap molecules whole). λ-DNA as Symeonidis and Karniadakis take it: contour length
    L = 21.1 µm, persistence length lp = 0.053 µm, so each of the M - 1 springs has
    Lspring/lp = 21.1/(0.053 (M - 1)) (99.5 for M = 5). Symeonidis and Karniadakis do not say how they map
    µm to DPD lengths; here Lspring = l_spring (default 8 rc: L = 32 rc, lp = 0.0804 rc), chosen
    so that the relaxation time is a few DPD time units, long enough for Weissenberg numbers
    of a few at shear rates the DPD fluid takes. The Underhill–Doyle correction for M > 2
    (Symeonidis and Karniadakis 2006, §3): lp_effective = lp (1 + 0.022 (M - 1)(1 - z))
    (M <= 20), z the chain's instantaneous fractional extension, enters as the global parameter WLC_LP_RATIO, set here
    for the start and refreshed by update_persistence_ratio() during a run.

    The chain starts as a random walk of steps sqrt(2 lp Lspring) (its rms spring length) from
    the box centre; the solvent uniformly at random.
    """
    if num_beads < 2 or num_beads > num_particles:
        raise ValueError("need 2 <= num_beads <= num_particles")
    lengths = tuple(float(x) for x in box)
    volume = lengths[0] * lengths[1] * lengths[2]
    lp = l_spring * LAMBDA_DNA["persistence_length"] * (num_beads - 1) / LAMBDA_DNA["contour_length"]
    rng = np.random.default_rng(seed)
    chain = list(range(num_beads))
    steps = rng.normal(size=(num_beads - 1, 3))
    steps *= np.sqrt(2 * lp * l_spring) / np.linalg.norm(steps, axis=1)[:, None]
    walk = 0.5 * np.array(lengths) + np.vstack([np.zeros(3), np.cumsum(steps, axis=0)])
    positions = np.vstack([walk, rng.uniform(0.0, 1.0, size=(num_particles - num_beads, 3)) * lengths])
    scene = _make_scene("wlc-shear", num_particles, num_particles / volume, positions, (chain,), lengths)
    springs = wlc_bond_force(list(zip(chain[:-1], chain[1:])), lp, l_spring, periodic=False, lp_ratio=True)
    ratio = underhill_doyle_ratio(fractional_extension(walk, l_spring * (num_beads - 1)), num_beads)
    springs.setGlobalParameterDefaultValue(0, ratio)
    springs.setForceGroup(FAST_FORCE_GROUP)
    scene.system.addForce(springs)
    scene.system.addForce(soft_repulsion_force(num_particles, a, native=native_force))
    return scene


_BUILDERS = {"ideal": ideal_scene, "soft": soft_scene, "polymer": polymer_scene, "fene-chains": fene_chains_scene,
             "wlc-shear": wlc_shear_scene}


def build_scene(name, **kwargs):
    """Build the scene called `name` (one of SCENES) with the builder's keyword arguments."""
    try:
        builder = _BUILDERS[name]
    except KeyError:
        raise ValueError(f"unknown scene {name!r}; known: {', '.join(SCENES)}") from None
    return builder(**kwargs)
