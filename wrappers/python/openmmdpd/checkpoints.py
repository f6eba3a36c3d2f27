"""Checkpoints that, when refused, leave the simulation as it was."""
import os

from .dpdplugin import _loadCheckpointBytes


def load_checkpoint(target, checkpoint):
    """Load a checkpoint into a Simulation or Context, or leave it exactly as it was.

    Like ``Simulation.loadCheckpoint`` / ``Context.loadCheckpoint``, except that a refused
    checkpoint (damaged, truncated, written by another integrator or for another System)
    leaves the Context's positions, velocities, time, step count, box, parameters and
    integrator state bit for bit as they were before the call.  OpenMM's own loaders restore
    OpenMM's part of the file before the integrator reads its part, so after a refusal there
    the Context holds the refused file's positions and velocities.

    :param target: the ``openmm.app.Simulation`` or ``openmm.Context`` to load into
    :param checkpoint: what ``Context.createCheckpoint()`` or ``Simulation.saveCheckpoint()``
        wrote: bytes, a file name, or a binary file object
    :raises openmm.OpenMMException: if the checkpoint is refused; its message says why
    """
    context = getattr(target, "context", target)
    if isinstance(checkpoint, (str, os.PathLike)):
        with open(checkpoint, "rb") as f:
            checkpoint = f.read()
    elif not isinstance(checkpoint, (bytes, bytearray)):
        checkpoint = checkpoint.read()
    _loadCheckpointBytes(context, bytes(checkpoint))
