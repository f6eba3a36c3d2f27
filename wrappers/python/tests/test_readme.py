"""Every ```python block of README.md, run as a script in a fresh interpreter at small sizes,
so that a broken example fails the suite.  Each block must be complete (its own imports)."""
import os
import re
import subprocess
import sys

import pytest

import openmmdpd

README = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "README.md")

# The examples' sizes, shrunk so that each runs in seconds.
SMALLER = [
    (re.compile(r"num_particles=\d+"), lambda m: "num_particles=500"),
    (re.compile(r"\.step\((\d+)\)"), lambda m: f".step({min(int(m.group(1)), 200)})"),
]


def readme_blocks():
    with open(README) as f:
        return re.findall(r"^```python\n(.*?)^```", f.read(), re.S | re.M)


def shrink(code):
    for pattern, replacement in SMALLER:
        code = pattern.sub(replacement, code)
    return code


def test_the_readme_has_its_examples():
    assert len(readme_blocks()) >= 3
    assert "step(200)" in shrink("simulation.step(10000)") and "num_particles=500" in shrink("num_particles=4000")


@pytest.mark.parametrize("index", range(len(readme_blocks())))
def test_readme_example_runs(index, tmp_path):
    code = shrink(readme_blocks()[index])
    # This package (wherever conftest found it) and the OpenMM it runs with.
    path = [os.path.dirname(os.path.dirname(openmmdpd.__file__))] + os.environ.get("PYTHONPATH", "").split(os.pathsep)
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(p for p in path if p))
    result = subprocess.run([sys.executable, "-c", code], cwd=str(tmp_path), env=env,
                            capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, f"README example {index}:\n{code}\n--- stderr:\n{result.stderr}"
