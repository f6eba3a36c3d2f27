"""Every ```python block of README.md and of the documentation's pages (docs/, the built site
left out), run as a script in a fresh interpreter at small sizes, so that a broken example
fails the suite.  Each block must be complete (its own imports)."""
import os
import re
import subprocess
import sys

import pytest

import openmmdpd

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..")
README = os.path.join(ROOT, "README.md")
DOCS = os.path.join(ROOT, "docs")

# The examples' sizes, shrunk so that each runs in seconds.
SMALLER = [
    (re.compile(r"num_particles=\d+"), lambda m: "num_particles=500"),
    (re.compile(r"\.step\((\d+)\)"), lambda m: f".step({min(int(m.group(1)), 200)})"),
    (re.compile(r"(calibrate_den_otter_clarke\([^()]*)\)"),
     lambda m: f"{m.group(1)}, equilibration_steps=100, num_blocks=4, block_steps=50)"),
]


def blocks(path):
    with open(path) as f:
        return re.findall(r"^```python\n(.*?)^```", f.read(), re.S | re.M)


def readme_blocks():
    return blocks(README)


def documents():
    """README.md, then every Markdown page of docs/ but the built site, relative to the root."""
    pages = []
    for folder, subfolders, files in os.walk(DOCS):
        subfolders[:] = sorted(d for d in subfolders if d not in ("_build", "_static"))
        pages += [os.path.join(folder, name) for name in sorted(files) if name.endswith(".md")]
    return [os.path.relpath(path, ROOT).replace(os.sep, "/") for path in [README] + pages]


def examples():
    """(document, index, code) for every python block, in document order."""
    return [(document, index, code) for document in documents()
            for index, code in enumerate(blocks(os.path.join(ROOT, document)))]


def shrink(code):
    for pattern, replacement in SMALLER:
        code = pattern.sub(replacement, code)
    return code


def test_the_readme_and_the_docs_have_their_examples():
    # The README's quick start, and the examples the guide pages carry (the README held eight).
    assert len(readme_blocks()) >= 1
    assert len(examples()) >= 8
    assert "docs/guide/integrators.md" in {document for document, _, _ in examples()}
    assert "step(200)" in shrink("simulation.step(10000)") and "num_particles=500" in shrink("num_particles=4000")


@pytest.mark.parametrize("document, index, code", examples(),
                         ids=[f"{document}-{index}" for document, index, _ in examples()])
def test_example_runs(document, index, code, tmp_path):
    code = shrink(code)
    # This package (wherever conftest found it) and the OpenMM it runs with.
    path = [os.path.dirname(os.path.dirname(openmmdpd.__file__))] + os.environ.get("PYTHONPATH", "").split(os.pathsep)
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(p for p in path if p))
    result = subprocess.run([sys.executable, "-c", code], cwd=str(tmp_path), env=env,
                            capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, f"{document} example {index}:\n{code}\n--- stderr:\n{result.stderr}"
