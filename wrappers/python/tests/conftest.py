"""Tests run against a built package: PYTHONPATH first, else the repository's build/python."""
import os
import sys

try:
    import openmmdpd  # noqa: F401
except ImportError:
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))
    sys.path.insert(0, os.path.join(root, "build", "python"))
