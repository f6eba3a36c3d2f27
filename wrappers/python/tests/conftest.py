"""Tests run against a built package: PYTHONPATH first, else the repository's build/python.

The source tree's wrappers/python/openmmdpd has no compiled module; when pytest runs from
wrappers/python, `python -m` puts that folder first on sys.path, where it would shadow the
built package.  It is taken off here (rather than with `python -P`, which needs Python 3.11).
"""
import os
import sys

_HERE = os.path.dirname(os.path.abspath(__file__))
_SOURCE_PACKAGE_PARENT = os.path.dirname(_HERE)
sys.path[:] = [p for p in sys.path if os.path.realpath(p or os.curdir) != os.path.realpath(_SOURCE_PACKAGE_PARENT)]

try:
    import openmmdpd  # noqa: F401
except ModuleNotFoundError as error:
    if error.name != "openmmdpd":
        raise
    root = os.path.dirname(os.path.dirname(_SOURCE_PACKAGE_PARENT))
    sys.path.insert(0, os.path.join(root, "build", "python"))
