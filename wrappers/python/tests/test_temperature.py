"""<kT> of every integrator against targets that do not come from this plugin.

Scenes: `ideal` (model A) and `soft` (model B, a = 25), N = 4000 in a 10^3 box, rho = 4,
gamma = 4.5, rc = 1, kT = 1, unit masses.  Each case runs long enough that its combined
error sigma = sqrt(sigma_stat^2 + systematic^2) is <= 0.002 (else it FAILS: a 1 % bias must
be detectable), and passes if |<kT> - target| <= 3 sigma.  sigma_stat = sqrt(g var / n), g the
statistical inefficiency (pymbar).  `pytest -s` prints every number.

Where the targets come from
---------------------------
1. Pair rules (Lowe, pair OU, Shardlow S1/S2), ideal gas: <kT> = 1 exactly at every dt.
   A pair update changes only the pair's relative normal velocity u, which under
   Maxwell-Boltzmann (MB) is N(0, kT/mu) and independent of the rest of the velocities.
   Lowe redraws u from that law; pair OU is the exact OU solution; Shardlow's explicit plus
   implicit halves give u' = ((1 - c) u + N/mu)/(1 + c), c = gamma wD h/(2 mu),
   N^2 = 2 kT gamma wD h, and Var u' = [(1-c)^2 kT/mu + 2 kT c/mu]/(1+c)^2 = kT/mu.  So each
   pair map, and a sweep of them in any order, keeps MB at fixed positions; with no force the
   drift r += dt v keeps uniform positions uniform and independent of v.  Uniform x MB is
   therefore stationary.  The same holds with the pair rule between two half drifts
   (LoweAndersenIntegrator's Middle splitting, "-mid"), its pairs found where it acts.
2. Velocity-Verlet family, ideal gas.  The thermostat forces are linear in v:
   F = -Gamma(r) v + B xi/sqrt(dt), B B^T = 2 kT Gamma.  With Gamma frozen a scheme splits
   into Gamma's eigenmodes; a mode of rate l is a 1-d recurrence in x = l dt (w = dt F,
   zeta ~ N(0, 2 kT x)) whose stationary variance f(x) kT solves C = A C A^T + Q (sympy):
     GW lambda: v' = (1-x/2) v + (1-lambda x) w/2 + zeta'/2, w' = -x v - lambda x w + zeta'
                -> f = 1/(1 + (lambda - 1/2) x)
     DPD-VV:    v' = (1-x/2)^2 v + (1-x/2) zeta/2 + zeta'/2
                -> f = 2(x^2-3x+4)/(x^2-4x+8) = 1 - x/4 + O(x^3)
     SC-VV:     (1+x/2) v' = (1-x/2) v + (zeta + zeta')/2 -> f = 1/(1 + x/2)
     EDPD:      (p, s) per mode, p_h = p - dt c s/2, s' from the recurrence with
                dh = c dt p_h, p' = p_h - dt c s'/2; either scheme, any alpha -> f = 1
   Averaged over the spectrum of Gamma: g = tr Gamma/3N = 4 pi gamma rho/90 = 2.513/ps (the
   per-particle friction) and Var = tr Gamma^2/3N - g^2 = (2/3) 4 pi gamma^2 rho/105 = 6.46/ps^2.
   But Gamma is not frozen: particles move ~rc in the ~1/g a mode takes to relax.
   * SC-VV is immune: y = (1+x/2) v - zeta/2 obeys y' = R y + zeta/(1+x/2),
     R = (1-x/2)/(1+x/2), which keeps y ~ N(0, kT) exactly whatever Gamma is; the drift
     r += dt y' then keeps uniform positions independent of y'.  So, at every dt,
     <kT> = <1/(1 + l dt/2)> = 1/(1 + g dt/2) + dt^2 Var/(4 (1 + g dt/2)^3) + O(dt^3 l^3)
     (the spectrum of 500-particle configurations gives the same to 1e-4).
   * GW and DPD-VV are not: the half-step velocity u that carries their state has, frozen,
     a covariance excess q x/2 (q = 2 - 2 lambda for GW, 1/2 for DPD-VV; f - 1 is that
     excess minus the x/2 lost by reading v half a kick away from u).  If Gamma changed
     faster than the modes relax,
     the excess would average to q dt <l^2>/(2g) instead, i.e. <kT> higher by q D dt,
     D = Var/(2g) = 1.29/ps.  Reality lies in between, so the target is
     f(g dt) + q D dt/2 with a systematic of +-q D dt/2, and dt keeps that <= 0.001.  (The
     per-particle recurrence alone would say GW-1/2 is exact at every dt; this plugin gives
     1.008 at dt = 0.01 on `ideal` and LAMMPS 1.006 on model B: the pair-motion term is real.)
   * EDPD is not analysed beyond f = 1: it gets a systematic of +-D dt.
   * Staggered with K = 1 and (mu, a, b) = (0, 0, 1) is GW exactly (to rounding, same seed,
     test_staggered.py), so its target is GW's at its lambda (0.65), with half the particles
     declared polymer so that the polymer path runs too.
3. Model B.  The same thermostat analysis with model B's structure: g_B = 1.663/ps,
   Var_B = 2.08/ps^2 (D_B = 0.624/ps), and the velocity-Verlet part's own O(dt^2) error,
   whose size is bounded by the weak-thermostat limit, where the Gibbs law of VV's shadow
   Hamiltonian p^2/2 + dt^2 p.V''.p/12 + ... gives <kT> = 1 - omega^2 dt^2/6 with
   omega^2 = <|F|^2>/(3N kT) = 45.6 (a thermostat that redraws every velocity each step
   leaves only O(dt^4)).  These three constants are static properties of model B, measured
   with OpenMM's own LangevinMiddleIntegrator and CustomNonbondedForce (no plugin code;
   test_model_b_constants re-measures them).  The pair rules are exact for the thermostat
   part (1. holds at any positions), so their target is 1 +- omega^2 dt^2/6.  GW lambda = 1/2
   is compared with LAMMPS (same model, N = 4000): 1.006, 1.010, 1.018, 1.042, 1.094 at
   dt = 0.01, 0.02, 0.03, 0.05, 0.07, each +-0.001.
"""
import math
import os
import zlib
from collections import namedtuple

import numpy as np
import openmm
import pytest
from openmm import unit
from pymbar import timeseries
from scipy.spatial import cKDTree

import openmmdpd
from openmmdpd import catalog, scenes

from dpdtest import KT, reduced_kT, set_velocities

N = 4000                       # 10^3 box at rho = 4
GAMMA, RHO = 4.5, 4.0
G_IDEAL = 4 * math.pi * GAMMA * RHO / 90                   # 2.513 /ps
VAR_IDEAL = 2 / 3 * 4 * math.pi * GAMMA ** 2 * RHO / 105   # 6.46 /ps^2
G_SOFT, VAR_SOFT, OMEGA2_SOFT = 1.663, 2.075, 45.6         # model B, OpenMM Langevin (above)
LAMMPS_GW_SOFT = {0.01: 1.006, 0.02: 1.010, 0.03: 1.018, 0.05: 1.042, 0.07: 1.094}
LAMMPS_ERROR = 0.001
SIGMA_LIMIT = 0.002            # the combined sigma that can still see a 1 % bias at 3 sigma
SIGMA_GOAL = 0.0018            # where sampling stops (a margin for the noise of g)
THREADS = os.environ.get("OPENMMDPD_TEST_THREADS", "2")

Case = namedtuple("Case", "integrator scene dt target systematic source slow exponent transverse", defaults=(2.0, None))


def structure(scene, transverse=None):
    """(g, Var, omega^2) of a scene; with transverse friction (gamma_perp, s_perp) on the ideal gas,
    g and Var of its friction matrix (ideal_gas_friction_moments)."""
    if transverse is not None:
        assert scene == "ideal"
        return (*ideal_gas_friction_moments(GAMMA, 2.0, *transverse), 0.0)
    return (G_IDEAL, VAR_IDEAL, 0.0) if scene == "ideal" else (G_SOFT, VAR_SOFT, OMEGA2_SOFT)


def ideal_gas_friction_moments(gamma, s, gamma_perp, s_perp, rho=4.0):
    """g = tr Gamma/3N and Var = tr Gamma^2/3N - g^2 of an ideal gas of unit masses (rc = 1)
    whose pair friction is A(r) = gamma wD e e^T + gamma_perp wD_perp (I - e e^T).  Gamma's
    diagonal blocks are sum_j A_ij and its off-diagonal ones -A_ij; with Poisson positions the
    directions of different pairs are independent, so the mean of A over directions,
    a(r) I, a = (gamma wD + 2 gamma_perp wD_perp)/3, gives the cross terms:
    g = rho int a d^3r and Var = (2/3) rho int tr A^2 d^3r, tr A^2 = gamma^2 wD^2 + 2 gamma_perp^2 wD_perp^2,
    with int (1 - r)^s 4 pi r^2 dr = 8 pi / ((s+1)(s+2)(s+3)).  Without transverse friction
    these are G_IDEAL = 4 pi gamma rho/90 and VAR_IDEAL = (2/3) 4 pi gamma^2 rho/105."""
    def moment(p):
        return 8 * math.pi / ((p + 1) * (p + 2) * (p + 3))
    g = rho * (gamma * moment(s) + 2 * gamma_perp * moment(s_perp)) / 3
    var = 2 * rho * (gamma ** 2 * moment(2 * s) + 2 * gamma_perp ** 2 * moment(2 * s_perp)) / 3
    return g, var


def velocity_verlet_case(integrator, scene, dt, slow=False, transverse=None):
    """Target and systematic of the VV family from the mode analysis (docstring, 2. and 3.)."""
    g, var, omega2 = structure(scene, transverse)
    x, d = g * dt, var / (2 * g)
    lam = {"GW": 0.5, "GW0.65": 0.65, "Staggered": 0.65}.get(integrator)
    if lam is not None:
        frozen, q = 1 / (1 + (lam - 0.5) * x), 2 - 2 * lam
    elif integrator == "DPD-VV":
        frozen, q = 2 * (x * x - 3 * x + 4) / (x * x - 4 * x + 8), 0.5
    elif integrator == "SC-VV":
        frozen, q = 1 / (1 + x / 2) + dt * dt * var / (4 * (1 + x / 2) ** 3), 0.0
    else:
        raise ValueError(integrator)
    motion = q * d * dt / 2
    return Case(integrator, scene, dt, frozen + motion, math.hypot(motion, omega2 * dt * dt / 6),
                f"modes f(g dt) + q D dt/2, q={q:g}", slow, 2.0, transverse)


def exact_case(integrator, scene, dt, slow=False, exponent=2.0, transverse=None):
    """Pair rules and EDPD: 1 from the thermostat; VV's O(dt^2) on model B, EDPD's motion term.
    The pair rules' 1 holds for any weight exponent s (1. does not depend on wD) and with
    transverse friction (gamma_perp, s_perp): its update is the same map on each axis across e."""
    g, var, omega2 = structure(scene)
    motion = var / (2 * g) * dt if integrator.startswith("EDPD") else 0.0
    return Case(integrator, scene, dt, 1.0, math.hypot(motion, omega2 * dt * dt / 6),
                "exact 1" + (" +- D dt" if motion else ""), slow, exponent, transverse)


def lammps_case(dt, slow=False):
    return Case("GW", "soft", dt, LAMMPS_GW_SOFT[dt], LAMMPS_ERROR, "LAMMPS", slow)


CASES = [
    # ideal gas: the pair rules at a long step, the VV family where their systematic is small
    *(exact_case(name, "ideal", 0.05) for name in ("Lowe", "PairOU", "S1", "S2")),
    # weight exponents s = 0.5 and 1 (wD = (1 - r/rc)^s), through the pair OU's exponential and Shardlow's halves
    exact_case("PairOU", "ideal", 0.05, exponent=0.5),
    exact_case("S1", "ideal", 0.05, exponent=1.0),
    # transverse friction (gamma_perp, s_perp) across e, each with another exponent along it
    exact_case("PairOU", "ideal", 0.05, exponent=1.0, transverse=(GAMMA, 2.0)),
    exact_case("S1", "ideal", 0.05, transverse=(GAMMA, 0.5)),
    exact_case("S2", "ideal", 0.05, transverse=(2 * GAMMA, 1.0)),
    velocity_verlet_case("SC-VV", "ideal", 0.01, transverse=(GAMMA, 2.0)),
    velocity_verlet_case("DPD-VV", "ideal", 0.002, slow=True, transverse=(GAMMA, 1.0)),
    # pairs found where O acts: OpenMM's DPDIntegrator, which finds them before the half
    # drift, runs 0.8 % hot here
    *(exact_case(name, "ideal", 0.1) for name in ("Lowe-mid", "PairOU-mid")),
    velocity_verlet_case("SC-VV", "ideal", 0.01),
    velocity_verlet_case("GW", "ideal", 0.0015, slow=True),
    velocity_verlet_case("GW0.65", "ideal", 0.002, slow=True),
    velocity_verlet_case("DPD-VV", "ideal", 0.003, slow=True),
    velocity_verlet_case("Staggered", "ideal", 0.002, slow=True),
    exact_case("EDPD-OneSided", "ideal", 0.001, slow=True),
    exact_case("EDPD-Symmetric", "ideal", 0.001, slow=True),
    # model B: smaller friction spread, so the VV family can take longer steps here
    *(lammps_case(dt) for dt in sorted(LAMMPS_GW_SOFT)),
    *(exact_case(name, "soft", 0.01) for name in ("Lowe", "PairOU", "S1", "Lowe-mid", "PairOU-mid")),
    exact_case("S2", "soft", 0.01, slow=True),
    velocity_verlet_case("GW0.65", "soft", 0.0045),
    velocity_verlet_case("DPD-VV", "soft", 0.005),
    velocity_verlet_case("Staggered", "soft", 0.0045),
    velocity_verlet_case("SC-VV", "soft", 0.01),
    exact_case("EDPD-OneSided", "soft", 0.0015, slow=True),
    exact_case("EDPD-Symmetric", "soft", 0.0015, slow=True),
]
EQUILIBRATION_TIME = {"ideal": 1.0, "soft": 3.0}   # ps; `soft` starts from random positions
SAMPLE_INTERVAL = 0.01                             # ps between kT samples (kT decorrelates in ~0.3)
CHUNK_TIME = 5.0                                   # ps sampled between checks of sigma
MIN_CHUNKS = 4                                     # so that g is estimated from >= 20 ps
MAX_SAMPLE_TIME = 400.0                            # ps; ~40 is typical, EDPD's memory needs ~200


def make_integrator(name, dt, exponent=2.0, transverse=None):
    if name.startswith("EDPD"):
        scheme = name.split("-")[1]
        # OneSided in its DPD limit (alpha dt = 100); Symmetric is unstable there, so a
        # 0.1-ps memory instead.
        alpha = 100 / dt if scheme == "OneSided" else 10.0
        integrator = openmmdpd.EDPDIntegrator(KT, GAMMA, 1.0, alpha, dt)
        integrator.setScheme(getattr(openmmdpd.EDPDIntegrator, scheme))
    elif name == "Staggered":
        integrator = openmmdpd.StaggeredDPDIntegrator(KT, GAMMA, 1.0, dt, 1)
        integrator.setRelaxationParameters(0, 0, 1)  # with K = 1: GW exactly
        integrator.setLambda(0.65)
        integrator.setPolymerParticles(list(range(0, N, 2)))
    else:
        integrator = catalog.integrators()[name](dt)
    integrator.setDefaultWeightExponent(exponent)
    if transverse is not None:
        integrator.setDefaultTransverseFriction(transverse[0])
        integrator.setDefaultTransverseWeightExponent(transverse[1])
    return integrator


def make_scene(case):
    scene = scenes.build_scene(case.scene, num_particles=N)
    if case.integrator == "Staggered":
        # The staggered integrator wants a force in its fast group; this one acts on nothing.
        fast = scenes.periodic_marker_force()
        fast.setForceGroup(scenes.FAST_FORCE_GROUP)
        scene.system.addForce(fast)
    return scene


def combined_sigma(samples, case):
    return math.hypot(mean_and_error(samples)[1], case.systematic)


def sample_kT(case, platform_name, seed):
    """kT samples after equilibration, in chunks until the combined sigma reaches
    SIGMA_GOAL (the fewest steps that can see a 1 % bias) or MAX_SAMPLE_TIME runs out."""
    scene = make_scene(case)
    integrator = make_integrator(case.integrator, case.dt, case.exponent, case.transverse)
    integrator.setRandomNumberSeed(seed)
    properties = {"Threads": THREADS} if platform_name == "CPU" else {}
    context = openmm.Context(scene.system, integrator, openmm.Platform.getPlatformByName(platform_name), properties)
    context.setPositions(scene.positions)
    set_velocities(context, scene.system, seed)  # no net momentum: kT = 2 KE/(3N - 3)
    integrator.step(round(EQUILIBRATION_TIME[case.scene] / case.dt))
    every = max(1, round(SAMPLE_INTERVAL / case.dt))
    chunk = round(CHUNK_TIME / (every * case.dt))
    samples = []
    while len(samples) < MAX_SAMPLE_TIME / (every * case.dt):
        for _ in range(chunk):
            integrator.step(every)
            samples.append(reduced_kT(context, N))
        if len(samples) >= MIN_CHUNKS * chunk and combined_sigma(np.array(samples), case) <= SIGMA_GOAL:
            break
    return np.array(samples), every


def mean_and_error(samples):
    """(mean, sqrt(g var/n), g) with g pymbar's statistical inefficiency."""
    g = timeseries.statisticalInefficiency(samples)
    return samples.mean(), math.sqrt(g * samples.var() / len(samples)), g


def parameters():
    for case in CASES:
        name = f"{case.integrator}-{case.scene}-dt{case.dt:g}" + (f"-s{case.exponent:g}" if case.exponent != 2 else "")
        if case.transverse is not None:
            name += "-perp{:g}-s{:g}".format(*case.transverse)
        seed = zlib.crc32(name.encode()) % 1000000 + 1  # fixed per case; 0 would mean "any"
        for platform_name in ("CPU", "Reference"):
            slow = case.slow or platform_name == "Reference"
            yield pytest.param(case, platform_name, seed, id=f"{platform_name}-{name}",
                               marks=[pytest.mark.slow] if slow else [])


@pytest.mark.parametrize("case, platform_name, seed", list(parameters()))
def test_kinetic_temperature(case, platform_name, seed):
    samples, every = sample_kT(case, platform_name, seed)
    mean, sigma_stat, g = mean_and_error(samples)
    sigma = math.hypot(sigma_stat, case.systematic)
    print(f"\n{platform_name} {case.integrator} {case.scene} dt={case.dt:g} N={N} steps={len(samples)}x{every}: "
          f"<kT> = {mean:.5f}, sigma_stat = {sigma_stat:.5f}, "
          f"g = {g:.1f}, target = {case.target:.5f} +- {case.systematic:.5f} ({case.source}), "
          f"sigma = {sigma:.5f}, |diff|/sigma = {abs(mean - case.target) / sigma:.2f}")
    assert sigma <= SIGMA_LIMIT, f"sigma = {sigma:.4f}: too little statistics to detect a 1 % bias"
    assert abs(mean - case.target) <= 3 * sigma, f"<kT> = {mean:.5f}, target {case.target:.5f} +- 3 x {sigma:.5f}"


# --- where G_SOFT, VAR_SOFT and OMEGA2_SOFT come from: OpenMM alone, no plugin code ---

def friction_moments(x, box, transverse=(0.0, 2.0)):
    """(tr Gamma, tr Gamma^2)/3N of the DPD friction matrix at positions x: Gamma has the
    diagonal blocks sum_j A_ij and off-diagonal blocks -A_ij, A = w e e^T + w_perp (I - e e^T),
    w = gamma (1 - r)^2, w_perp = gamma_perp (1 - r)^s_perp."""
    pairs = cKDTree(x % box, boxsize=box).query_pairs(1.0, output_type="ndarray")
    d = x[pairs[:, 0]] - x[pairs[:, 1]]
    d -= box * np.round(d / box)
    r = np.linalg.norm(d, axis=1)
    w, w_perp = GAMMA * (1 - r) ** 2, transverse[0] * (1 - r) ** transverse[1]
    along = (d[:, :, None] * d[:, None, :]) / (r * r)[:, None, None]
    block = w[:, None, None] * along + w_perp[:, None, None] * (np.eye(3) - along)
    diagonal = np.zeros((len(x), 3, 3))
    np.add.at(diagonal, pairs[:, 0], block)
    np.add.at(diagonal, pairs[:, 1], block)
    trace = np.trace(block, axis1=1, axis2=2)
    return 2 * trace.sum() / (3 * len(x)), ((diagonal ** 2).sum() + 2 * (block ** 2).sum()) / (3 * len(x))


@pytest.mark.parametrize("transverse", [(0.0, 2.0), (GAMMA, 2.0), (GAMMA, 0.5)])
def test_friction_moments_of_the_ideal_gas_match_the_formulas(transverse):
    rng = np.random.default_rng(1)
    g, m2 = np.mean([friction_moments(rng.uniform(0, 10, (N, 3)), 10.0, transverse) for _ in range(4)], axis=0)
    expected_g, expected_var = ideal_gas_friction_moments(GAMMA, 2.0, *transverse)
    if transverse[0] == 0:
        assert (expected_g, expected_var) == pytest.approx((G_IDEAL, VAR_IDEAL), rel=1e-12)
    assert g == pytest.approx(expected_g, rel=0.01)
    assert m2 - g * g == pytest.approx(expected_var, rel=0.03)


@pytest.mark.slow
def test_model_b_constants():
    """Model B sampled by OpenMM's LangevinMiddleIntegrator with a CustomNonbondedForce."""
    scene = scenes.soft_scene(num_particles=N, native_force=False)
    integrator = openmm.LangevinMiddleIntegrator(KT, 1.0, 0.005)
    integrator.setRandomNumberSeed(3)
    context = openmm.Context(scene.system, integrator, openmm.Platform.getPlatformByName("CPU"), {"Threads": THREADS})
    context.setPositions(scene.positions)
    context.setVelocitiesToTemperature(KT, 3)
    integrator.step(2000)
    values = []
    for _ in range(40):
        integrator.step(100)
        state = context.getState(getPositions=True, getForces=True)
        x = state.getPositions(asNumpy=True).value_in_unit(unit.nanometer)
        f = state.getForces(asNumpy=True).value_in_unit(unit.kilojoule_per_mole / unit.nanometer)
        g, m2 = friction_moments(x, 10.0)
        values.append((g, m2 - g * g, (f * f).sum() / (3 * N)))
    g, var, omega2 = np.mean(values, axis=0)
    print(f"\nmodel B: g = {g:.4f}, Var = {var:.4f}, omega^2 = {omega2:.3f}")
    assert (g, var, omega2) == pytest.approx((G_SOFT, VAR_SOFT, OMEGA2_SOFT), rel=0.01)
