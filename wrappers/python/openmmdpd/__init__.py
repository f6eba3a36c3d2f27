"""openmm-dpd: dissipative particle dynamics integrators for OpenMM.

Importing the package loads its kernel plugins from the folder it is installed in, so
no environment variable and no write access to OpenMM's plugin folder are needed.
"""
import os as _os

import openmm as _openmm  # loads OpenMM's own plugins (the CPU platform) first

from .dpdplugin import (DPDSoftRepulsionForce, DPDThermostatIntegrator, DPDVVIntegrator, EDPDIntegrator,
                        LoweAndersenIntegrator, ShardlowIntegrator, StaggeredDPDIntegrator)
from .units import KT_TEMPERATURE, kT_from_temperature, reduced_temperature, strip_units

__all__ = ["DPDSoftRepulsionForce", "DPDThermostatIntegrator", "DPDVVIntegrator", "ShardlowIntegrator",
           "LoweAndersenIntegrator", "EDPDIntegrator", "StaggeredDPDIntegrator", "KT_TEMPERATURE", "kT_from_temperature",
           "reduced_temperature", "strip_units", "loaded_plugins"]


def _load_kernel_plugins():
    here = _os.path.dirname(_os.path.abspath(__file__))
    loaded = []
    for name in ("libOpenMMDPDReference.so", "libOpenMMDPDCPU.so"):
        path = _os.path.join(here, name)
        if _os.path.exists(path):
            _openmm.Platform.loadPluginLibrary(path)
            loaded.append(path)
    return tuple(loaded)


loaded_plugins = _load_kernel_plugins()
