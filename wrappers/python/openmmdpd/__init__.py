"""openmm-dpd: dissipative particle dynamics integrators for OpenMM.

Importing the package loads its kernel plugins from the folder it is installed in, so
no environment variable and no write access to OpenMM's plugin folder are needed.
"""
import os as _os

import openmm as _openmm  # loads OpenMM's own plugins (the CPU platform) first

from . import _build


def _check_openmm_version(built, running):
    """ImportError unless OpenMM `running` has the major.minor `built` (of the plugins).

    The same rule as the C++ plugins' (platforms/core/OpenMMVersionCheck), checked here before
    the compiled module is imported: one built against another OpenMM may not even link.
    """
    if built.split(".")[:2] != running.split(".")[:2]:
        raise ImportError(f"openmmdpd was built against OpenMM {built} but the openmm imported ({_openmm.__file__}) "
                          f"is {running}; OpenMM's internal platform data may be laid out differently. Rebuild "
                          f"openmm-dpd against this OpenMM (cmake -DOPENMM_DIR=<its prefix>), or import the "
                          f"OpenMM {built} it was built against.")


def _load_openmm_plugins(plugin_dir):
    """OpenMM's own platforms, if `import openmm` registered none (an upstream OpenMM looks in
    /usr/local/openmm/lib/plugins unless OPENMM_PLUGIN_DIR is set): from the OpenMM built against."""
    platform = _openmm.Platform
    names = {platform.getPlatform(i).getName() for i in range(platform.getNumPlatforms())}
    if names <= {"Reference"} and _os.path.isdir(plugin_dir):
        platform.loadPluginsFromDirectory(plugin_dir)


_check_openmm_version(_build.openmm_version, _openmm.Platform.getOpenMMVersion())
_load_openmm_plugins(_build.openmm_plugin_dir)

from .dpdplugin import (DenOtterClarkeIntegrator, DPDSoftRepulsionForce, DPDThermostatIntegrator,  # noqa: E402
                        DPDVVIntegrator, EDPDIntegrator, LoweAndersenIntegrator, MDPDForce, ShardlowIntegrator,
                        StaggeredDPDIntegrator)
from .units import DPDUnits, KT_TEMPERATURE, kT_from_temperature, reduced_temperature, strip_units  # noqa: E402
from .flory_huggins import a_from_chi, chi_from_a  # noqa: E402
from . import _downcast, _low_temperature  # noqa: E402
from ._low_temperature import LowTemperatureWarning  # noqa: E402

_INTEGRATORS = (DPDVVIntegrator, ShardlowIntegrator, LoweAndersenIntegrator, EDPDIntegrator,
                DenOtterClarkeIntegrator, StaggeredDPDIntegrator)
# XmlSerializer.deserialize / clone, System.getForce(s) and CompoundIntegrator.getIntegrator
# give our integrators and forces back as their own classes, not as base Integrator / Force.
_downcast.install(_INTEGRATORS, (DPDSoftRepulsionForce, MDPDForce))
# A temperature of 0-10 K given to an integrator is almost surely a reduced kT read as kelvin.
_low_temperature.install(DPDThermostatIntegrator, _INTEGRATORS)

__version__ = _build.version

__all__ = ["DPDSoftRepulsionForce", "MDPDForce", "DPDThermostatIntegrator", "DPDVVIntegrator", "ShardlowIntegrator",
           "LoweAndersenIntegrator", "EDPDIntegrator", "StaggeredDPDIntegrator", "DenOtterClarkeIntegrator",
           "calibrate_den_otter_clarke", "load_checkpoint", "KT_TEMPERATURE", "kT_from_temperature",
           "reduced_temperature", "strip_units", "DPDUnits", "LowTemperatureWarning", "a_from_chi", "chi_from_a",
           "apply_thermostat_parameters", "loaded_plugins", "skipped_plugins", "scenes", "forcefield", "packer",
           "electrostatics", "add_smeared_electrostatics", "__version__"]


def _load_kernel_plugins():
    """(paths loaded, {path: why not} for the GPU plugins that could not load).

    The GPU plugins are built only where OpenMM has those platforms, and load only where their
    platform's runtime is (the CUDA plugin needs libcuda, i.e. a driver): without it they are
    skipped, as OpenMM skips its own platform plugins.
    """
    here = _os.path.dirname(_os.path.abspath(__file__))
    loaded, skipped = [], {}
    for name in ("libOpenMMDPDReference.so", "libOpenMMDPDCPU.so", "libOpenMMDPDOpenCL.so", "libOpenMMDPDCUDA.so"):
        path = _os.path.join(here, name)
        if not _os.path.exists(path):
            continue
        try:
            _openmm.Platform.loadPluginLibrary(path)
            loaded.append(path)
        except _openmm.OpenMMException as error:
            if name in ("libOpenMMDPDReference.so", "libOpenMMDPDCPU.so"):
                raise
            skipped[path] = str(error)
    return tuple(loaded), skipped


loaded_plugins, skipped_plugins = _load_kernel_plugins()

# After the plugins: `openmmdpd.scenes` works after a plain `import openmmdpd`.
from . import scenes  # noqa: E402
# Registers the DPD tags with app.ForceField: a DPD force field read before this would lose them.
from . import forcefield, packer  # noqa: E402
from . import electrostatics  # noqa: E402
from .electrostatics import add_smeared_electrostatics  # noqa: E402
from .forcefield import apply_thermostat_parameters  # noqa: E402
from .calibration import calibrate_den_otter_clarke  # noqa: E402
from .checkpoints import load_checkpoint  # noqa: E402
