"""Import openmmdpd from the source tree only when no built copy is on the path."""
import os
import sys

try:
    import openmmdpd  # noqa: F401  (a build tree on PYTHONPATH wins)
except ImportError:
    sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
