#!/usr/bin/env bash
# Builds the documentation site into docs/_build/html: Doxygen XML of the public C++
# headers, then Sphinx with every warning an error (-W), nitpicky cross-references (-n),
# and all warnings reported before failing (--keep-going).  Needs no build of the plugin and
# no network: MathJax comes from Debian's libjs-mathjax.
set -euo pipefail
cd "$(dirname "$0")/.."
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
