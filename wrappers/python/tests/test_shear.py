"""Lees–Edwards shear of model B (rho 4, a 25, gamma 4.5, N = 4000 in a 10^3 box).

The imposed flow v_x = rate (y - Ly/2) is set at the start, so the steady state needs no
start-up.  Every `EVERY` steps a frame gives the velocity profile over 10 bins of y, its
least-squares slope and residuals, and the peculiar temperature (openmmdpd.shear).  Errors
are standard errors from pymbar's statistical inefficiency over the frames.

- The profile: the mean slope is the rate within 2 % (and within 3 sigma), with sigma small
  enough to see a 2 % error at 3 sigma.  Across the sliding boundary the velocity changes by
  exactly U = rate Ly, so a jump there takes its share from the slope inside.  A boundary
  layer (pairs across the boundary pulled toward each other, as without the image velocity)
  would lift the bin next to y = 0 above the fit and drop the one next to Ly below it: their
  residual difference is 0 within 3 sigma, sigma <= 1 % of U.
  The slope's slow hydrodynamic decay (tau ~ Ly^2 / (4 pi^2 nu) ~ 10 time units) sets the
  sample times: 100 time units at rate 0.5, 1800 at rate 0.1 (dt 0.04 and a frame every time
  unit there, to afford it).
- The peculiar <kT> at dt 0.01 and rate 0.1 is 1 within 1 % (sigma <= 0.0033).
Each case takes 10-90 s: marked slow.  `pytest -s` prints every number.
"""
import numpy as np
import openmm
import pytest
from openmm import unit

import openmmdpd
from openmmdpd import shear
from openmmdpd.analysis import standard_error
from openmmdpd.catalog import integrators
from openmmdpd.scenes import build_scene

SCHEMES = ("GW", "S1", "Lowe", "PairOU")
BINS = 10


def sheared_run(name, rate, dt, sample_time, frame_every=0.1, equilibrate=5.0, seed=3):
    """Frames of model B under shear: (slopes, edge residuals (n, 2), peculiar kT, kT components (n, 3),
    the box height Ly)."""
    scene = build_scene("soft", seed=seed)
    integrator = integrators("soft")[name](dt)
    integrator.setShearRate(rate / unit.picosecond)
    integrator.setRandomNumberSeed(seed)
    context = openmm.Context(scene.system, integrator, openmm.Platform.getPlatformByName("CPU"))
    positions = scene.positions.value_in_unit(unit.nanometer)
    height = scene.system.getDefaultPeriodicBoxVectors()[1][1].value_in_unit(unit.nanometer)
    context.setPositions(positions)
    context.setVelocitiesToTemperature(openmmdpd.KT_TEMPERATURE, seed)
    v = context.getState(getVelocities=True).getVelocities(asNumpy=True).value_in_unit(unit.nanometer / unit.picosecond)
    v[:, 0] += shear.streaming_velocity(positions[:, 1], rate, height)
    context.setVelocities(v)
    integrator.step(int(round(equilibrate / dt)))
    masses = np.ones(len(positions))
    slopes, edges, temperatures, components = [], [], [], []
    every = int(round(frame_every / dt))
    for _ in range(int(round(sample_time / frame_every))):
        integrator.step(every)
        state = context.getState(getPositions=True, getVelocities=True)
        r, v = state.getPositions(asNumpy=True), state.getVelocities(asNumpy=True)
        slope, residuals = shear.profile_slope(*shear.velocity_profile(r, v, height, BINS))
        slopes.append(slope)
        edges.append((residuals[0], residuals[-1]))
        kT, per_axis = shear.peculiar_temperature(r, v, masses, rate, height)
        temperatures.append(kT)
        components.append(per_axis)
    return np.array(slopes), np.array(edges), np.array(temperatures), np.array(components), height


@pytest.mark.slow
@pytest.mark.parametrize("rate, dt, sample_time, frame_every", [(0.5, 0.01, 100.0, 0.1), (0.1, 0.04, 1800.0, 1.0)])
@pytest.mark.parametrize("name", SCHEMES)
def test_velocity_profile_is_linear_with_the_imposed_slope(name, rate, dt, sample_time, frame_every):
    slopes, edges, _, components, height = sheared_run(name, rate, dt, sample_time, frame_every)
    jump = rate * height  # U = rate Ly
    slope, sigma = slopes.mean(), standard_error(slopes)
    edge, edge_sigma = edges.mean(axis=0), [standard_error(edges[:, k]) for k in range(2)]
    layer, layer_sigma = np.mean(edges[:, 0] - edges[:, 1]), standard_error(edges[:, 0] - edges[:, 1])
    print(f"\n{name} rate {rate} dt {dt}: slope/rate {slope / rate:.4f} +- {sigma / rate:.4f}; "
          f"edge residuals {edge[0]:+.4f} +- {edge_sigma[0]:.4f}, {edge[1]:+.4f} +- {edge_sigma[1]:.4f}, "
          f"difference {layer:+.4f} +- {layer_sigma:.4f}; "
          f"kT components {np.round(components.mean(axis=0), 4)}")
    assert sigma <= 0.02 * rate / 3, f"sigma {sigma} too large to see a 2 % error"
    assert abs(slope - rate) <= 0.02 * rate and abs(slope - rate) <= 3 * sigma
    assert layer_sigma <= 0.01 * jump
    assert abs(layer) <= 3 * layer_sigma, "the profile has a boundary layer at the sliding boundary"


@pytest.mark.slow
@pytest.mark.parametrize("name", SCHEMES)
def test_peculiar_temperature_at_low_rate(name):
    _, _, temperatures, components, _ = sheared_run(name, 0.1, 0.01, 40.0)
    kT, sigma = temperatures.mean(), standard_error(temperatures)
    print(f"\n{name} rate 0.1 dt 0.01: peculiar kT {kT:.4f} +- {sigma:.4f}, components "
          f"{np.round(components.mean(axis=0), 4)}")
    assert sigma <= 0.01 / 3
    assert abs(kT - 1) <= 0.01
