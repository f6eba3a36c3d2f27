"""Observables of a sheared DPD fluid (docs/theory/lees-edwards.md): peculiar velocities, the
temperature from them, and the velocity profile, in reduced units.

Under Lees–Edwards shear (`DPDThermostatIntegrator.setShearRate`) the flow is along x and
its gradient along y; the integrators keep molecules in 0 <= y < Ly and report lab-frame
velocities (their `computeKineticEnergy`, and so OpenMM's reporters, include the flow).
These functions remove it: the peculiar velocity is u = v - rate (y - Ly/2) x̂, less the
mean of that over the particles (total momentum is not conserved under shear: the jumps
at the boundary move it), with y the particle's height as the Context stores it, the one
its velocity belongs to.  Arguments may be OpenMM Quantities or plain arrays in nm, nm/ps,
amu and 1/ps.
"""
import numpy as np
from openmm import unit

from .analysis import _array

__all__ = ["streaming_velocity", "impose_flow", "remove_net_momentum", "peculiar_velocities", "peculiar_temperature", "velocity_profile", "profile_slope"]


def streaming_velocity(y, rate, box_height):
    """The imposed flow's x velocity at height y: rate (y - Ly/2)."""
    return _rate(rate) * (np.asarray(y, dtype=float) - 0.5 * box_height)


def impose_flow(context, rate):
    """Add the imposed flow rate (y - Ly/2) along x to a Context's velocities, y as the Context
    stores it (the integrators wrap a molecule with the velocity jump that goes with it)."""
    state = context.getState(getPositions=True, getVelocities=True)
    y = state.getPositions(asNumpy=True).value_in_unit(unit.nanometer)[:, 1]
    velocities = state.getVelocities(asNumpy=True).value_in_unit(unit.nanometer / unit.picosecond)
    velocities[:, 0] += streaming_velocity(y, rate, state.getPeriodicBoxVectors()[1][1].value_in_unit(unit.nanometer))
    context.setVelocities(velocities)


def remove_net_momentum(context):
    """Subtract the centre-of-mass velocity from a Context's velocities. Under shear a net momentum
    along y moves the centre of mass along x at -rate v_y per unit time (each boundary crossing
    changes v_x by rate Ly), so a sheared run should start without one."""
    system = context.getSystem()
    masses = np.array([system.getParticleMass(i).value_in_unit(unit.dalton) for i in range(system.getNumParticles())])
    velocities = context.getState(getVelocities=True).getVelocities(asNumpy=True).value_in_unit(
        unit.nanometer / unit.picosecond)
    context.setVelocities(velocities - masses @ velocities / masses.sum())


def _rate(rate):
    return float(_array(rate, unit.picosecond**-1))


def peculiar_velocities(positions, velocities, rate, box_height):
    """(N, 3) velocities less the imposed flow and less their mean."""
    r = _array(positions, unit.nanometer).reshape(-1, 3)
    u = _array(velocities, unit.nanometer / unit.picosecond).reshape(-1, 3).copy()
    u[:, 0] -= streaming_velocity(r[:, 1], rate, float(_array(box_height, unit.nanometer)))
    return u - u.mean(axis=0)


def peculiar_temperature(positions, velocities, masses, rate, box_height):
    """(kT, (kT_x, kT_y, kT_z)) from the peculiar velocities: sum m u^2 over 3N - 3 degrees of
    freedom (N - 1 per component).  Viscous heating at high rates makes kT_x > kT_y ~ kT_z."""
    u = peculiar_velocities(positions, velocities, rate, box_height)
    m = _array(masses, unit.dalton).reshape(-1)
    per_axis = np.sum(m[:, None] * u * u, axis=0) / (len(u) - 1)
    return float(per_axis.mean()), tuple(float(x) for x in per_axis)


def velocity_profile(positions, velocities, box_height, bins=10):
    """(bin centres, mean v_x per bin) over 0 <= y < Ly.  A bead of a molecule whose centre
    is inside but which is itself just outside counts in the edge bin (its velocity belongs
    to where it is, so it is not folded)."""
    height = float(_array(box_height, unit.nanometer))
    y = _array(positions, unit.nanometer).reshape(-1, 3)[:, 1]
    vx = _array(velocities, unit.nanometer / unit.picosecond).reshape(-1, 3)[:, 0]
    index = np.clip(np.floor(y / height * bins).astype(int), 0, bins - 1)
    counts = np.bincount(index, minlength=bins)
    sums = np.bincount(index, weights=vx, minlength=bins)
    centres = (np.arange(bins) + 0.5) * height / bins
    return centres, sums / np.maximum(counts, 1)


def profile_slope(centres, means):
    """The least-squares slope dv_x/dy of a velocity profile, and its residuals per bin."""
    slope, intercept = np.polyfit(centres, means, 1)
    return float(slope), means - (slope * centres + intercept)


if __name__ == "__main__":
    from .options import not_a_command
    not_a_command("shear",
                  "It measures a sheared fluid's peculiar velocities, temperature and velocity profile from Python "
                  "(openmmdpd.shear.peculiar_temperature, velocity_profile, ...); `python3 -m openmmdpd.viscosity` runs"
                  " sheared fluids (see its --help).")
