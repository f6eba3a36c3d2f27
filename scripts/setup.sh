#!/usr/bin/env bash
# Installs (idempotently) every Debian package the project needs to build, test and document.
# Runs `apt-get update` at most once per machine, and only when something is missing.
set -euo pipefail

PACKAGES=(
  build-essential cmake swig
  libopenmm-dev libopenmm-plugins python3-simtk
  librandom123-dev libxxhash-dev libeigen3-dev libgtest-dev
  python3-dev python3-numpy python3-scipy python3-pytest python3-matplotlib python3-tqdm
  python3-pymbar python3-mdanalysis
  pocl-opencl-icd ocl-icd-opencl-dev opencl-headers
  python3-sphinx python3-myst-parser python3-sphinx-rtd-theme doxygen python3-breathe libjs-mathjax
)

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if [ ${#missing[@]} -gt 0 ]; then
  SUDO=""
  [ "$(id -u)" -eq 0 ] || SUDO="sudo"
  echo "setup: installing ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
else
  echo "setup: all packages present"
fi
