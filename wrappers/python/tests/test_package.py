"""What `import openmmdpd` gives a new user: its version, its scenes, and a clear refusal of
an OpenMM other than the one it was built against."""
import os
import subprocess
import sys

import openmm
import pytest

import openmmdpd


def test_version_and_what_it_was_built_against():
    assert openmmdpd.__version__ == openmmdpd._build.version and openmmdpd.__version__.count(".") == 2
    running = openmm.Platform.getOpenMMVersion().split(".")[:2]
    assert openmmdpd._build.openmm_version.split(".") == running


def test_scenes_after_a_plain_import(tmp_path):
    path = [os.path.dirname(os.path.dirname(openmmdpd.__file__))] + os.environ.get("PYTHONPATH", "").split(os.pathsep)
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(p for p in path if p))
    code = "import openmmdpd; print(openmmdpd.scenes.build_scene('ideal', num_particles=100).system.getNumParticles())"
    # From a folder of its own: `python -c` puts the current folder first on sys.path.
    result = subprocess.run([sys.executable, "-c", code], cwd=str(tmp_path), env=env, capture_output=True, text=True,
                            timeout=60)
    assert result.returncode == 0, result.stderr
    assert result.stdout.split() == ["100"]


def test_openmm_of_another_major_minor_is_refused():
    openmmdpd._check_openmm_version("8.5", "8.5.2")
    openmmdpd._check_openmm_version("7.7", "7.7")
    # 8.4 changed the layout of the platform data the kernels read.
    with pytest.raises(ImportError, match=r"built against OpenMM 8\.3 but the openmm imported .* is 8\.4\.0"):
        openmmdpd._check_openmm_version("8.3", "8.4.0")
    with pytest.raises(ImportError, match="Rebuild openmm-dpd against this OpenMM"):
        openmmdpd._check_openmm_version("7.7", "8.5.2")


def test_openmm_platforms_found_without_environment_variables():
    names = [openmm.Platform.getPlatform(i).getName() for i in range(openmm.Platform.getNumPlatforms())]
    assert "CPU" in names


def test_every_kernel_plugin_is_loaded_or_skipped_with_a_reason():
    """A GPU plugin whose platform runtime is missing (CUDA without a driver) is skipped, and
    says why; the Reference and CPU plugins always load."""
    here = os.path.dirname(openmmdpd.__file__)
    built = {os.path.join(here, name) for name in os.listdir(here)
             if name.startswith("libOpenMMDPD") and name.endswith(".so") and name != "libOpenMMDPD.so"}
    assert built == set(openmmdpd.loaded_plugins) | set(openmmdpd.skipped_plugins)
    assert all(reason for reason in openmmdpd.skipped_plugins.values())
    assert not any(os.path.basename(p) in ("libOpenMMDPDReference.so", "libOpenMMDPDCPU.so")
                   for p in openmmdpd.skipped_plugins)
