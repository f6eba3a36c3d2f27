"""Thermostat exceptions: a pair with factor f has friction gamma f and noise sigma sqrt(f)
(fluctuation-dissipation kept), 0 excludes it.  The definition checked here is that an
exception with factor f on every pair of a group of particles gives the trajectory that a
type pair with friction f times as large gives (same seed), the thermostat's part of the
pressure tensor included: a sigma scaled by f instead of sqrt(f) fails it.  Also: the setters and their checks, bonds to exceptions, XML, and an
excluded pair that receives no thermostat force at all, for every integrator on Reference
and CPU.  CPU = Reference with exceptions is in tests/TestPlatformsAgree.cpp.

The statistics: the exact pair rules keep <kT> = 1 with the bonded pairs of chains excluded
or scaled, momentum stays to rounding with every thermostat option on, and the beads of
chains in a DPD solvent with their bonds excluded from the thermostat are at the solvent's
kT.  The error rules are test_temperature.py's (sigma <= 0.002, pass within 3 sigma)."""
import itertools
import math
import zlib

import numpy as np
import openmm
import pytest

import openmmdpd
from openmmdpd import catalog, scenes
from dpdtest import KT, momentum, properties, reduced_kT, set_velocities
from test_temperature import SIGMA_GOAL, SIGMA_LIMIT, THREADS, mean_and_error

FRICTION, CUTOFF, DT = 4.5, 1.0, 0.02
GROUP = range(0, 300, 3)  # type 1: a tenth of the fluid, so most of their pairs are with type 0


def every_integrator():
    """Our integrators by name: the catalog's (but Langevin and OpenMM's) and extended DPD."""
    makers = {name: make for name, make in catalog.integrators("soft").items() if name not in ("Langevin", "OpenMM-DPD")}
    makers["EDPD"] = lambda dt: openmmdpd.EDPDIntegrator(KT, FRICTION, CUTOFF, 10.0, dt)
    makers["Staggered"] = staggered
    return makers


def staggered(dt):
    """Two sub-steps for the group's particles (the System gets a fast force group for them)."""
    integrator = openmmdpd.StaggeredDPDIntegrator(KT, FRICTION, CUTOFF, dt, 2)
    integrator.setPolymerParticles(list(GROUP))
    return integrator


INTEGRATORS = every_integrator()
# The schemes with transverse friction: the velocity-Verlet family, Shardlow and the pair OU.
TRANSVERSE = ("GW", "GW0.65", "DPD-VV", "SC-VV", "S1", "S2", "PairOU", "PairOU-mid")


def final_state(integrator, platform_name, steps=20):
    """Positions, velocities and (where the integrator has one) the thermostat's part of the pressure tensor."""
    scene = scenes.build_scene("soft", num_particles=1000)
    if isinstance(integrator, openmmdpd.StaggeredDPDIntegrator):
        fast = scenes.periodic_marker_force()
        fast.setForceGroup(scenes.FAST_FORCE_GROUP)
        scene.system.addForce(fast)
    integrator.setRandomNumberSeed(5)
    has_pressure = not isinstance(integrator, (openmmdpd.DenOtterClarkeIntegrator, openmmdpd.StaggeredDPDIntegrator))
    if has_pressure:
        integrator.setPressureTensorEnabled(True)
    context = openmm.Context(scene.system, integrator, openmm.Platform.getPlatformByName(platform_name),
                             properties(platform_name))
    context.setPositions(scene.positions)
    context.setVelocitiesToTemperature(KT, 7)
    integrator.step(steps)
    state = context.getState(getPositions=True, getVelocities=True)
    pressure = integrator.getAveragePressureTensor(integrator.PressureThermostat)._value if has_pressure else []
    return state.getPositions(asNumpy=True)._value, state.getVelocities(asNumpy=True)._value, np.array(pressure)


def group_runs(name, factor):
    """(with exceptions, with a type pair): group pairs carry the exception in the first; in the
    second they are type pair (1, 1), with friction f times the default.  Every other pair is
    alike in both."""
    with_exceptions, with_type_pair = INTEGRATORS[name](DT), INTEGRATORS[name](DT)
    for integrator in (with_exceptions, with_type_pair):
        for i in GROUP:
            integrator.setParticleType(i, 1)
        integrator.addTypePair(0, 1, FRICTION, CUTOFF)
    with_type_pair.addTypePair(1, 1, FRICTION * factor, CUTOFF)
    with_exceptions.addTypePair(1, 1, FRICTION, CUTOFF)
    for i, j in itertools.combinations(GROUP, 2):
        with_exceptions.addThermostatException(i, j, factor)
    return with_exceptions, with_type_pair


def expect_same_final_state(name, with_exceptions, with_type_pair, platform_name):
    expected, actual = final_state(with_type_pair, platform_name), final_state(with_exceptions, platform_name)
    for what, e, a in zip(("positions", "velocities", "thermostat pressure"), expected, actual):
        assert np.max(np.abs(a - e), initial=0) <= 1e-9 * np.max(np.abs(e), initial=0), f"{name}: {what}"


@pytest.mark.parametrize("platform_name", ["Reference", "CPU"])
@pytest.mark.parametrize("factor", [0.0, 0.3])
@pytest.mark.parametrize("name", sorted(INTEGRATORS))
def test_an_exception_is_the_friction_scaled_by_its_factor(name, factor, platform_name):
    expect_same_final_state(name, *group_runs(name, factor), platform_name)


@pytest.mark.parametrize("platform_name", ["Reference", "CPU"])
@pytest.mark.parametrize("factor", [0.0, 0.3])
@pytest.mark.parametrize("name", TRANSVERSE)
def test_an_exception_scales_the_transverse_friction_alike(name, factor, platform_name):
    # As above, with transverse friction 3 (exponent 1) on every pair: the exceptions scale it
    # by f, its noise by sqrt(f), as a type pair with f times the transverse friction.
    with_exceptions, with_type_pair = group_runs(name, factor)
    for integrator in (with_exceptions, with_type_pair):
        integrator.setDefaultTransverseFriction(3.0)
        integrator.setDefaultTransverseWeightExponent(1.0)
    with_type_pair.setTypePairTransverseFriction(1, 3.0 * factor, 1.0)
    expect_same_final_state(name, with_exceptions, with_type_pair, platform_name)


@pytest.mark.parametrize("platform_name", ["Reference", "CPU"])
@pytest.mark.parametrize("name", sorted(INTEGRATORS))
def test_an_excluded_pair_gets_no_thermostat_force(name, platform_name):
    # Two particles 0.5 apart, no conservative force: with f = 0 nothing changes their
    # velocities, transverse friction included where the scheme has it.
    integrator = INTEGRATORS[name](DT)
    integrator.addThermostatException(1, 0, 0.0)
    if name in TRANSVERSE:
        integrator.setDefaultTransverseFriction(FRICTION)
    if isinstance(integrator, openmmdpd.StaggeredDPDIntegrator):
        integrator.setPolymerParticles([0])
    system = openmm.System()
    for _ in range(2):
        system.addParticle(1.0)
    system.setDefaultPeriodicBoxVectors(*(openmm.Vec3(*row) for row in 4 * np.eye(3)))
    marker = scenes.periodic_marker_force()
    marker.setForceGroup(scenes.FAST_FORCE_GROUP)  # the staggered integrator's fast group; the others integrate every group
    system.addForce(marker)
    context = openmm.Context(system, integrator, openmm.Platform.getPlatformByName(platform_name), properties(platform_name))
    context.setPositions([openmm.Vec3(1, 1, 1), openmm.Vec3(1.5, 1, 1)])
    velocities = [openmm.Vec3(0.3, -0.2, 0.1), openmm.Vec3(-0.3, 0.2, 0.4)]
    context.setVelocities(velocities)
    integrator.step(5)
    after = context.getState(getVelocities=True).getVelocities(asNumpy=True)._value
    assert np.array_equal(after, np.array([list(v) for v in velocities])), name


def test_setters_getters_and_checks():
    integrator = openmmdpd.ShardlowIntegrator(KT, FRICTION, CUTOFF, DT)
    assert integrator.addThermostatException(3, 1, 0.5) == 0
    assert integrator.getNumThermostatExceptions() == 1
    assert integrator.getThermostatExceptionParameters(0) == [3, 1, 0.5]
    for args, message in [((1, 3, 0.2), "particles 1, 3 already have a thermostat exception"),
                          ((2, 2, 0.2), "two different particle indices"),
                          ((-1, 2, 0.2), "two different particle indices"),
                          ((4, 5, -0.1), r"must be in \[0, 1\]"),
                          ((4, 5, 1.5), r"must be in \[0, 1\]"),
                          ((4, 5, float("nan")), r"must be in \[0, 1\]")]:
        with pytest.raises(openmm.OpenMMException, match=message):
            integrator.addThermostatException(*args)
    assert integrator.getNumThermostatExceptions() == 1
    integrator.setThermostatExceptionParameters(0, 1, 3, 0.0)  # its own pair again: allowed
    assert integrator.getThermostatExceptionParameters(0) == [1, 3, 0.0]
    with pytest.raises(openmm.OpenMMException, match="index must be in"):
        integrator.getThermostatExceptionParameters(1)


def test_bonds_give_their_one_two_and_one_three_pairs_once():
    integrator = openmmdpd.DPDVVIntegrator(KT, FRICTION, CUTOFF, DT)
    integrator.createThermostatExceptionsFromBonds([(0, 1), (1, 2), (2, 3), (1, 0)], 0.0, 0.5)
    pairs = {tuple(sorted(integrator.getThermostatExceptionParameters(k)[:2])): integrator.getThermostatExceptionParameters(k)[2]
             for k in range(integrator.getNumThermostatExceptions())}
    assert pairs == {(0, 1): 0.0, (1, 2): 0.0, (2, 3): 0.0, (0, 2): 0.5, (1, 3): 0.5}
    with pytest.raises(openmm.OpenMMException, match="already have a thermostat exception"):
        integrator.createThermostatExceptionsFromBonds([(5, 6), (2, 3)], 0.0, 1.0)
    assert integrator.getNumThermostatExceptions() == 5  # nothing added by the refused call
    only12 = openmmdpd.DPDVVIntegrator(KT, FRICTION, CUTOFF, DT)
    only12.createThermostatExceptionsFromBonds([(0, 1), (1, 2)], 0.0, 1.0)
    assert only12.getNumThermostatExceptions() == 2
    only13 = openmmdpd.DPDVVIntegrator(KT, FRICTION, CUTOFF, DT)
    only13.createThermostatExceptionsFromBonds([(0, 1), (1, 2)], 1.0, 0.5)  # factor 1: no exception listed
    assert [only13.getThermostatExceptionParameters(k) for k in range(only13.getNumThermostatExceptions())] == [[0, 2, 0.5]]


def test_a_particle_beyond_the_system_is_refused_at_context_creation():
    scene = scenes.build_scene("soft", num_particles=500)
    integrator = openmmdpd.DPDVVIntegrator(KT, FRICTION, CUTOFF, DT)
    integrator.addThermostatException(0, 500, 0.0)
    with pytest.raises(openmm.OpenMMException, match="particles 0, 500 names a particle beyond the System's 500"):
        openmm.Context(scene.system, integrator, openmm.Platform.getPlatformByName("Reference"))


def test_xml_keeps_the_exceptions():
    integrator = openmmdpd.LoweAndersenIntegrator(KT, FRICTION, CUTOFF, DT)
    integrator.addThermostatException(0, 1, 0.0)
    integrator.addThermostatException(2, 7, 0.25)
    copy = openmmdpd.LoweAndersenIntegrator.cast(openmm.XmlSerializer.deserialize(openmm.XmlSerializer.serialize(integrator)))
    assert [copy.getThermostatExceptionParameters(k) for k in range(2)] == [[0, 1, 0.0], [2, 7, 0.25]]
    xml = openmm.XmlSerializer.serialize(integrator).replace('factor=".25"', 'factor="2"')
    assert 'factor="2"' in xml
    with pytest.raises(openmm.OpenMMException, match=r"must be in \[0, 1\]"):
        openmm.XmlSerializer.deserialize(xml)


# --- <kT> with exceptions: the pair rules stay exact -------------------------------------------

BOND_K = 7.0                   # harmonic springs of rest length 0 (Nikunen et al.'s chains)
CHAIN_LENGTH = 10
EXACT_RULES = ("Lowe", "PairOU", "S1", "S2")


def harmonic_chains(num_particles, density, num_chains, seed=1):
    """Chains of CHAIN_LENGTH beads joined by springs BOND_K of rest length 0, the leading
    particles; unit masses, periodic cube.  Returns (system, positions, bonds); the chains
    start as random walks with the springs' own Gaussian bond vectors, the rest uniform."""
    rng = np.random.default_rng(seed)
    box = (num_particles / density) ** (1 / 3)
    num_beads = num_chains * CHAIN_LENGTH
    walks = rng.uniform(0, box, (num_chains, 1, 3)) + np.cumsum(
        rng.normal(scale=math.sqrt(1 / BOND_K), size=(num_chains, CHAIN_LENGTH, 3)), axis=1)
    positions = np.vstack([walks.reshape(num_beads, 3), rng.uniform(0, box, (num_particles - num_beads, 3))])
    system = openmm.System()
    for _ in range(num_particles):
        system.addParticle(1.0)
    system.setDefaultPeriodicBoxVectors(*(openmm.Vec3(*row) for row in box * np.eye(3)))
    bonds = [(i, i + 1) for i in range(num_beads - 1) if (i + 1) % CHAIN_LENGTH]
    system.addForce(scenes.harmonic_bond_force(bonds, k=BOND_K))
    return system, positions, bonds


def sample(context, integrator, dt, measure, equilibration, min_time, systematic=0.0, every=1, max_time=2000.0):
    """measure() every `every` steps after `equilibration` ps, in 5-ps chunks, until the combined
    sigma (statistical and systematic) reaches SIGMA_GOAL after at least min_time ps."""
    integrator.step(round(equilibration / dt))
    chunk = round(5.0 / (every * dt))
    samples = []
    while len(samples) * every * dt < max_time:
        for _ in range(chunk):
            integrator.step(every)
            samples.append(measure())
        if (len(samples) * every * dt >= min_time
                and math.hypot(mean_and_error(np.array(samples))[1], systematic) <= SIGMA_GOAL):
            break
    return np.array(samples)


def case_seed(name):
    return zlib.crc32(name.encode()) % 1000000 + 1  # fixed per case; 0 would mean "any"


def exact_rule_cases():
    """(rule, factor, transverse friction) for every exact rule at f = 0 and 0.5, and for those
    with transverse friction (gamma_perp = gamma) at 0.5."""
    cases = [(name, factor, 0.0) for name in EXACT_RULES for factor in (0.0, 0.5)]
    return cases + [(name, 0.5, FRICTION) for name in EXACT_RULES if name in TRANSVERSE]


@pytest.mark.parametrize("platform_name", [pytest.param("Reference", marks=pytest.mark.slow), "CPU"])
@pytest.mark.parametrize("name, factor, transverse", exact_rule_cases())
def test_the_pair_rules_stay_exact_with_bonded_pairs_excepted(name, factor, transverse, platform_name):
    """<kT> = 1 at dt = 0.1 for Lowe and the pair OU (thermostat after the Verlet step), S1
    (before it) and S2 (half before, half after), with every 1-2 pair of the chains at factor f,
    and with transverse friction (its update keeps Maxwell-Boltzmann velocities as the one
    along e does: test_temperature.py, 1.).

    Why exact: 1000 unit masses at rho = 4, all in chains of 10, whose only force is the
    springs, linear (rest length 0; bond vectors stay far below half the box).  For a linear
    force K q, velocity Verlet from one whole step to the next keeps
    H~ = p^2/2 + q.K(1 - dt^2 K/4).q/2 exactly (the 2x2 map of each mode of K), so it keeps
    exp(-H~/kT); a pair update with factor f is the update of a pair with friction f gamma,
    which keeps Maxwell-Boltzmann velocities at fixed positions (test_temperature.py, 1.),
    f = 0 doing nothing.  So exp(-H~/kT) is stationary, and its velocities are exactly at kT,
    at any dt below Verlet's 2/omega (here dt omega_max = 0.53).  Not so with the thermostat
    between two half drifts (the "-mid" splittings): the drift-kick-drift map it sees keeps a
    form that is not p^2/2 plus a potential.  Bonds as topology only, on the ideal gas, would
    test little: a bonded pair would be within the cutoff no more often than any other
    (4 pi rc^3/3V = 1.7 % here), whereas the springs keep 93 % of them within it.

    What a noise scaled by f instead of sqrt(f) would give: the excepted pairs then act as a
    bath at f kT.  They carry 16 % of the pair weight sum wD here, so f = 0.5 gives them
    8.9 % of the friction, and the friction-weighted mean of the two baths puts <kT> near
    1 - 0.5 x 0.089 = 0.96, some 20 sigma off.  (f = 0 checks instead that an excluded pair
    gets no noise either: noise without friction would heat the chains.)

    sigma <= 0.0018 (statistical, pymbar); at least 100 ps, 25 times the slowest Rouse time
    of a chain (~4 ps), so that the statistical inefficiency is measured."""
    dt, n = 0.1, 1000
    label = f"{platform_name}-{name}-f{factor:g}" + (f"-perp{transverse:g}" if transverse else "")
    seed = case_seed(label)
    system, positions, bonds = harmonic_chains(n, 4.0, n // CHAIN_LENGTH)
    integrator = catalog.integrators()[name](dt)
    integrator.createThermostatExceptionsFromBonds(bonds, factor, 1.0)
    integrator.setDefaultTransverseFriction(transverse)
    integrator.setRandomNumberSeed(seed)
    context = openmm.Context(system, integrator, openmm.Platform.getPlatformByName(platform_name), properties(platform_name))
    context.setPositions(positions)
    set_velocities(context, system, seed)  # no net momentum: kT = 2 KE/(3N - 3)
    samples = sample(context, integrator, dt, lambda: reduced_kT(context, n), equilibration=10.0, min_time=100.0)
    mean, sigma, g = mean_and_error(samples)
    print(f"\n{label} dt={dt:g}: <kT> = {mean:.5f}, sigma = {sigma:.5f}, g = {g:.1f}, samples = {len(samples)}")
    assert sigma <= SIGMA_LIMIT, f"sigma = {sigma:.4f}: too little statistics to detect a 1 % bias"
    assert abs(mean - 1.0) <= 3 * sigma, f"<kT> = {mean:.5f}, target 1 +- 3 x {sigma:.5f}"


# --- momentum with every thermostat option on --------------------------------------------------

def with_every_option(integrator, positions, box, transverse):
    """Group particles type 1 (friction 3, weight exponent 1 against type 0), default exponent
    0.5 (EDPD refuses exponents other than 2), transverse friction where the scheme has it
    (4.5, and 2 with exponent 0.5 against type 0), and exceptions from bonds that join each
    group particle to its two nearest other particles: the 1-2 pairs excluded, the 1-3 pairs
    at 0.5.  The bonds join the group to the rest only, so no pair is both 1-2 and 1-3."""
    for i in GROUP:
        integrator.setParticleType(i, 1)
    pair = integrator.addTypePair(0, 1, 3.0, CUTOFF)
    if not isinstance(integrator, openmmdpd.EDPDIntegrator):
        integrator.setDefaultWeightExponent(0.5)
        integrator.setTypePairWeightExponent(pair, 1.0)
    if transverse:
        integrator.setDefaultTransverseFriction(FRICTION)
        integrator.setTypePairTransverseFriction(pair, 2.0, 0.5)
    others = np.array([i for i in range(len(positions)) if i not in set(GROUP)])
    bonds = []
    for i in GROUP:
        d = positions[others] - positions[i]
        d -= box * np.round(d / box)
        bonds += [(i, int(j)) for j in others[np.argsort((d * d).sum(axis=1))[:2]]]
    integrator.createThermostatExceptionsFromBonds(bonds, 0.0, 0.5)
    factors = [integrator.getThermostatExceptionParameters(k)[2] for k in range(integrator.getNumThermostatExceptions())]
    assert factors.count(0.0) == 2 * len(GROUP) and factors.count(0.5) >= len(GROUP)
    return integrator


@pytest.mark.parametrize("platform_name", ["Reference", "CPU"])
@pytest.mark.parametrize("name", sorted(INTEGRATORS))
def test_momentum_is_conserved_with_every_thermostat_option(name, platform_name):
    # A net momentum of its own, and masses 1 and 2 (the group), so that the pair impulses
    # must be equal and opposite in momentum, not in velocity (den Otter-Clarke takes one
    # mass only).
    scene = scenes.build_scene("soft", num_particles=1000)
    box = scene.system.getDefaultPeriodicBoxVectors()[0][0]._value
    if name != "OC":
        for i in GROUP:
            scene.system.setParticleMass(i, 2.0)
    if name == "Staggered":
        fast = scenes.periodic_marker_force()
        fast.setForceGroup(scenes.FAST_FORCE_GROUP)
        scene.system.addForce(fast)
    integrator = with_every_option(INTEGRATORS[name](DT), scene.positions._value, box, name in TRANSVERSE)
    integrator.setRandomNumberSeed(3)
    context = openmm.Context(scene.system, integrator, openmm.Platform.getPlatformByName(platform_name), properties(platform_name))
    context.setPositions(scene.positions)
    context.setVelocitiesToTemperature(KT, 4)
    before = momentum(context, scene.system)
    v0 = context.getState(getVelocities=True).getVelocities(asNumpy=True)._value
    masses = np.array([scene.system.getParticleMass(i)._value for i in range(1000)])
    integrator.step(20)
    v1 = context.getState(getVelocities=True).getVelocities(asNumpy=True)._value
    scale = (masses * np.linalg.norm(v0, axis=1)).sum()  # what rounding acts on: sum of |m v|
    assert np.linalg.norm(before) > 1.0
    assert np.abs(momentum(context, scene.system) - before).max() <= 1e-9 * scale, name
    assert np.abs(v1 - v0).max() > 1.0, name  # not trivially: the velocities changed a lot


# --- a polymer in a DPD solvent, its bonds excluded from the thermostat -------------------------

@pytest.mark.slow
def test_chain_beads_in_a_solvent_are_at_the_solvent_temperature():
    """100 chains of 10 (springs k = 7, rest length 0) in a soft-repulsion solvent, N = 3000,
    rho = 3, a = 25 between all particles, gamma = 4.5, every 1-2 pair excluded from the
    thermostat, Shardlow S1 at dt = 0.01 on the CPU.  The beads' <kT> (= sum m v^2 over the
    beads / (3 N_b (1 - 1/N)): zero total momentum takes 1/N of each particle's share) is 1
    from the pair rule (test_temperature.py, 1.) up to velocity Verlet's O(dt^2), bounded by
    omega_b^2 dt^2/6 with omega_b^2 = <|F|^2>/3 over the beads (test_temperature.py, 3.),
    measured here (about 51): a systematic of 0.0009, combined with the statistical error
    into sigma <= 0.0018.  At least 300 ps: the beads' kT decorrelates in ~0.8 ps (a 500-ps
    run: 0.9985 +- 0.0010), and pymbar found about half that in 100-ps runs."""
    dt, n, num_chains = 0.01, 3000, 100
    num_beads = num_chains * CHAIN_LENGTH
    system, positions, bonds = harmonic_chains(n, 3.0, num_chains)
    system.addForce(scenes.soft_repulsion_force(n, 25.0))
    integrator = catalog.integrators()["S1"](dt)
    integrator.createThermostatExceptionsFromBonds(bonds, 0.0, 1.0)
    integrator.setRandomNumberSeed(11)
    context = openmm.Context(system, integrator, openmm.Platform.getPlatformByName("CPU"), {"Threads": THREADS})
    context.setPositions(positions)
    set_velocities(context, system, 11)
    integrator.step(round(5.0 / dt))
    squares = []
    for _ in range(10):
        integrator.step(50)
        f = context.getState(getForces=True).getForces(asNumpy=True)._value[:num_beads]
        squares.append((f * f).sum() / (3 * num_beads))
    omega2 = np.mean(squares)
    systematic = omega2 * dt * dt / 6

    def beads_kT():
        v = context.getState(getVelocities=True).getVelocities(asNumpy=True)._value[:num_beads]
        return (v * v).sum() / (3 * num_beads * (1 - 1 / n))

    samples = sample(context, integrator, dt, beads_kT, equilibration=0.0, min_time=300.0, systematic=systematic, every=2)
    mean, sigma_stat, g = mean_and_error(samples)
    sigma = math.hypot(sigma_stat, systematic)
    print(f"\nchain beads, S1 dt={dt:g}: <kT> = {mean:.5f}, sigma_stat = {sigma_stat:.5f}, omega_b^2 = {omega2:.1f}, "
          f"systematic = {systematic:.5f}, sigma = {sigma:.5f}, g = {g:.1f}, samples = {len(samples)}")
    assert sigma <= SIGMA_LIMIT, f"sigma = {sigma:.4f}: too little statistics to detect a 1 % bias"
    assert abs(mean - 1.0) <= 3 * sigma, f"<kT> = {mean:.5f}, target 1 +- 3 x {sigma:.5f}"
