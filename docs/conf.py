"""Sphinx configuration of the openmm-dpd documentation (built by scripts/docs.sh)."""
import os
import re

here = os.path.dirname(os.path.abspath(__file__))


def _project_version():
    # One version for the whole project: the one CMakeLists.txt gives the plugin.
    with open(os.path.join(here, "..", "CMakeLists.txt")) as cmake:
        return re.search(r"project\(openmm-dpd VERSION ([0-9.]+)", cmake.read()).group(1)


project = "openmm-dpd"
author = "The openmm-dpd developers"
copyright = "The openmm-dpd developers"
version = release = _project_version()

extensions = [
    "myst_parser",
    "sphinx.ext.mathjax",
    "breathe",
]

source_suffix = {".md": "markdown"}
root_doc = "index"
# results/ holds the tools' generated reports; they are pages of the site too, reached from
# the validation page's (hidden) table of contents.
exclude_patterns = ["_build", "_static"]

# --- MyST: Markdown pages with LaTeX maths ------------------------------------------------
myst_enable_extensions = [
    "dollarmath",  # $...$ inline and $$...$$ display
    "amsmath",     # \begin{align} ... \end{align} and friends as display blocks
    "deflist",
    "colon_fence",
]
myst_heading_anchors = 3
# The MathJax configuration below is MathJax 2's; MyST would write a MathJax 3 one.
myst_update_mathjax = False

# --- MathJax, offline ---------------------------------------------------------------------
# scripts/docs.sh copies Debian's MathJax 2 (libjs-mathjax) into _static/mathjax, so the
# site renders equations without a network.  Without that copy (a plain sphinx-build on a
# machine with a network) Sphinx's default, MathJax 3 from a CDN, is used.
if os.path.exists(os.path.join(here, "_static", "mathjax", "MathJax.js")):
    mathjax_path = "mathjax/MathJax.js?config=TeX-AMS_SVG"
    # Only what Sphinx marked as maths is typeset: the rest of the page may hold dollar signs.
    mathjax2_config = {
        "tex2jax": {"processClass": "math", "ignoreClass": "document", "processEscapes": True},
        "SVG": {"font": "TeX"},
        "showMathMenu": False,
    }

# --- HTML ---------------------------------------------------------------------------------
html_theme = "sphinx_rtd_theme"
html_title = f"openmm-dpd {release}"
html_static_path = ["_static"] if os.path.isdir(os.path.join(here, "_static")) else []
html_theme_options = {"navigation_depth": 3}
html_show_sourcelink = False

# --- C++ API through Doxygen XML (breathe) --------------------------------------------------
breathe_projects = {"openmm-dpd": os.path.join(here, "_build", "doxygen", "xml")}
breathe_default_project = "openmm-dpd"
# Undocumented getters and enums are API too (and the targets of other members' types).
breathe_default_members = ("members", "undoc-members")

# -n (nitpicky) asks every cross-reference to resolve.  OpenMM's own classes are documented
# by OpenMM, not here, and there is no network for an inventory of its pages: references to
# them stay plain text.
nitpick_ignore_regex = [
    ("cpp:identifier", r"OpenMM(::.*)?"),
]
nitpick_ignore = [
    # Doxygen links the word "OpenMM" in comments to OpenMM's namespace, which has no page here.
    ("std:ref", "namespaceOpenMM"),
    # The namespace part of a qualified name (DPDPlugin::X): Sphinx's C++ domain has no
    # declaration a namespace could resolve to; the class it qualifies does resolve.
    ("cpp:identifier", "DPDPlugin"),
    # An unscoped enumerator as a default argument (getAveragePressureTensor(int part =
    # PressureTotal)): breathe leaves an empty symbol of that name in the class scope, which
    # keeps Sphinx from declaring the enumerator there.  The enumerator is documented, under
    # its enum PressurePart.
    ("cpp:identifier", "PressureTotal"),
]
