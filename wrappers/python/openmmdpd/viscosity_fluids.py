"""The fluids whose viscosity `python3 -m openmmdpd.viscosity` measures, and Groot–Warren's
kinetic-theory estimate of it, shared by viscosity (which runs) and viscosity_report (which reports)."""
import math

from .catalog import FRICTION

# model-a is Nikunen et al.'s model A (no conservative force: the soft scene at a = 0), where
# Groot–Warren's estimate applies as made.
SCENES = {"model-a": dict(density=4.0, a=0.0), "model-b": dict(density=4.0, a=25.0),
          "gw-fluid": dict(density=3.0, a=25.0)}


def groot_warren_estimate(density, gamma=FRICTION, kT=1.0, rc=1.0):
    """Groot–Warren's kinetic-theory viscosity (docs/theory/pressure-tensor.md, w_D = (1 - r/rc)^2, unit
    masses, no conservative force): rho D/2 + 2 pi gamma rho^2 rc^5/1575 with
    D = 45 kT/(2 pi gamma rho rc^3).  A rough guide, not a target."""
    diffusion = 45 * kT / (2 * math.pi * gamma * density * rc**3)
    return density * diffusion / 2 + 2 * math.pi * gamma * density**2 * rc**5 / 1575
