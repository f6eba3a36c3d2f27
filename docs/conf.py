"""Sphinx configuration of the openmm-dpd documentation (built by scripts/docs.sh)."""
import os
import re
import sys

from sphinx.errors import ConfigError

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
    "sphinx.ext.autodoc",
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
# Docstrings write `name` for code, as Markdown does; reStructuredText's default would be italics.
default_role = "code"

html_theme = "sphinx_rtd_theme"
html_title = f"openmm-dpd {release}"
html_static_path = ["_static"]
html_css_files = ["wide.css"]
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
    # The same in Python: the base classes autodoc shows (openmm.openmm.Integrator, Force)
    # and the exception that the functions raise (openmm.OpenMMException).
    (r"py:(class|exc)", r"openmm(\..*)?"),
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
    # SWIG writes a C++ default argument as ":type part: int, optional", and the Python
    # domain takes each word of a :type: field for a class.
    ("py:class", "optional"),
]

# --- Python API through autodoc ---------------------------------------------------------------
# autodoc imports `openmmdpd`, which needs the compiled module (_dpdplugin, the SWIG proxies in
# dpdplugin.py, the kernel plugins): the build's package, $OPENMMDPD_PYTHON_PATH if set (as
# scripts/docs.sh sets it), else <repo>/build/python.  Without it the site is not built: mocked
# imports would give the Python reference pages without a single class's methods, and
# nothing would say so.
_package_parent = os.path.abspath(os.environ.get("OPENMMDPD_PYTHON_PATH")
                                  or os.path.join(here, "..", "build", "python"))
if os.path.isdir(os.path.join(_package_parent, "openmmdpd")):
    sys.path.insert(0, _package_parent)
try:
    import openmmdpd  # noqa: E402,F401
    import openmmdpd.dpdplugin  # noqa: E402,F401  (the source tree's package has no such module)
except ImportError as error:
    raise ConfigError(
        f"the Python API reference (docs/api/python*.md) needs the built package openmmdpd, which did not "
        f"import from {_package_parent} ({error}). Build the plugin first (bash scripts/build.sh), or set "
        f"OPENMMDPD_PYTHON_PATH to the folder that holds a built openmmdpd/.") from error

autodoc_default_options = {
    # SWIG's proxies give every class the property `thisown` (who deletes the C++ object):
    # plumbing, not API.
    "exclude-members": "thisown",
}
autodoc_member_order = "bysource"
# A class's entry holds its constructor's parameters too (SWIG documents them on __init__).
autoclass_content = "both"
# Signatures as Python shows them (SWIG writes `def getTemperature(self)`): no type hints to
# resolve, so -n has nothing to chase in them.
autodoc_typehints = "none"


# SWIG's docstrings are the headers' Doxygen comments, plain text rather than
# reStructuredText: a "- item" list straight after a line of text, formulas indented as a
# block, |x| and * as maths.  Read as RST they are errors and wrong markup, so the prose of
# every docstring of the SWIG module is made RST here (its :param:/:type: fields, which
# SWIG writes as RST, are kept): special characters escaped, a blank line around each list,
# and an indented block after a blank line as a literal block.  The Python modules written
# by hand (openmmdpd/*.py) are RST already and pass unchanged.
_SWIG_MODULE = "openmmdpd.dpdplugin"
_FIELD = re.compile(r"^(:(?:param|type|rtype|return|returns|raises?)\b[^:]*:)(.*)$")
_BULLET = re.compile(r"^- ")


def _rst_text(text):
    text = text.replace("\\", "\\\\")
    text = re.sub(r"([*|`])", r"\\\1", text)
    return re.sub(r"(?<=\w)_(?!\w)", r"\\_", text)  # name_ is a reference


def _swig_docstring_as_rst(app, what, name, obj, options, lines):
    if getattr(obj, "__module__", None) != _SWIG_MODULE or not lines:
        return
    out, in_list, in_literal = [], False, False
    for line in lines:
        stripped, indent = line.strip(), len(line) - len(line.lstrip())
        previous = out[-1] if out else ""
        if not stripped:
            out.append("")
            continue
        if in_literal and indent > 0:
            out.append(line)
            continue
        in_literal = False
        field = _FIELD.match(line)
        if field:
            if previous and not _FIELD.match(previous) and not previous.startswith(" "):
                out.append("")
            out.append(field.group(1) + _rst_text(field.group(2)))
            in_list = False
            continue
        if _BULLET.match(line):
            if previous and not in_list:
                out.append("")
            in_list = True
            out.append(line[:2] + _rst_text(line[2:]))
            continue
        if in_list and indent > 0:
            out.append(line[:indent] + _rst_text(line[indent:]))  # a list item goes on
            continue
        if indent > 0 and not previous:
            # a block set off by indentation (formulas): literal, as written
            out += ["::", "", line]
            in_literal, in_list = True, False
            continue
        if in_list and previous:
            out.append("")  # the list ends
        in_list = False
        out.append(_rst_text(line))
    lines[:] = out


def setup(app):
    app.connect("autodoc-process-docstring", _swig_docstring_as_rst)
