#!/usr/bin/env bash
# Builds the documentation site into docs/_build/html: Doxygen XML of the public C++
# headers, then Sphinx with every warning an error (-W), nitpicky cross-references (-n),
# and all warnings reported before failing (--keep-going); then checks with
# wrappers/python/tests/test_api_reference.py that the API reference documents every public
# C++ class and method and every name of openmmdpd.__all__.  Needs no network (MathJax comes
# from Debian's libjs-mathjax), but needs a build of the plugin: the Python API reference is
# generated (autodoc) from the built package, $OPENMMDPD_PYTHON_PATH/openmmdpd.  Without it
# the build stops and says so.
set -euo pipefail
cd "$(dirname "$0")/.."

# The built package: $OPENMMDPD_PYTHON_PATH, else that of build/ or build-openmm8/ (in this
# order) that was built against the OpenMM python3 imports here (scripts/test.sh builds the
# site with OpenMM 8's PYTHONPATH still set from its second suite), else build/python.
if [ -z "${OPENMMDPD_PYTHON_PATH:-}" ]; then
  OPENMMDPD_PYTHON_PATH="$PWD/build/python"
  running=$(/usr/bin/python3 -c 'import openmm; print(openmm.Platform.getOpenMMVersion())' 2>/dev/null | cut -d. -f1,2 || true)
  for dir in build build-openmm8; do
    built=$(sed -n 's/^openmm_version = "\(.*\)"$/\1/p' "$dir/python/openmmdpd/_build.py" 2>/dev/null || true)
    if [ -n "$running" ] && [ "$built" = "$running" ]; then
      OPENMMDPD_PYTHON_PATH="$PWD/$dir/python"
      break
    fi
  done
fi
export OPENMMDPD_PYTHON_PATH
echo "docs: the Python API reference from $OPENMMDPD_PYTHON_PATH/openmmdpd"
bash scripts/setup.sh

# MathJax 2 with SVG output (no web fonts to fetch): the loader, one combined configuration,
# the TeX input, the SVG output with its TeX font, and the extensions the TeX input loads.
mathjax_src=/usr/share/javascript/mathjax
mathjax_dst=docs/_static/mathjax
rm -rf "$mathjax_dst"
mkdir -p "$mathjax_dst"
(cd "$mathjax_src" && cp -rL --parents \
  MathJax.js config/TeX-AMS_SVG.js extensions jax/input/TeX jax/element \
  jax/output/SVG/jax.js jax/output/SVG/config.js jax/output/SVG/autoload jax/output/SVG/fonts/TeX \
  localization/en "$OLDPWD/$mathjax_dst")

rm -rf docs/_build/doxygen
mkdir -p docs/_build/doxygen
(cd docs && doxygen Doxyfile)

# -E: read every page again, so that every run reports every warning (and sees new Doxygen XML).
/usr/bin/python3 -m sphinx -E -W --keep-going -n -b html docs docs/_build/html "$@"
echo "docs: docs/_build/html/index.html"

# The API reference is complete: run here, after the site exists, so that it always runs
# (the test suite skips it when there is no site yet).
PYTHONPATH="$OPENMMDPD_PYTHON_PATH${PYTHONPATH:+:$PYTHONPATH}" \
  /usr/bin/python3 -m pytest -q -p no:cacheprovider wrappers/python/tests/test_api_reference.py
