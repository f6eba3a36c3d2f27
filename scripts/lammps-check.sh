#!/usr/bin/env bash
# openmm-dpd and LAMMPS side by side on exported models (python3 -m openmmdpd.lammps_check):
# builds LAMMPS once, with DPD-BASIC, DPD-REACT, MOLECULE and OPENMP (no MPI), from Debian's
# source package (about 6 minutes on 2 cores; kept in $LAMMPS_BUILD_DIR, by default
# ~/.cache/openmmdpd-lammps), then runs the comparison (about 25 minutes). Not part of CI.
#
#     bash scripts/lammps-check.sh [options of openmmdpd.lammps_check]
set -euo pipefail
cd "$(dirname "$0")/.."
version="20220106.git7586adbb6a+ds1"
cache="${LAMMPS_BUILD_DIR:-$HOME/.cache/openmmdpd-lammps}"
lmp="$cache/build/lmp"
if [ ! -x "$lmp" ] || ! "$lmp" -h | grep -c OPENMP > /dev/null; then  # -c reads all: no SIGPIPE
  mkdir -p "$cache"
  echo "lammps-check: building LAMMPS $version in $cache"
  [ -f "$cache/lammps.tar.xz" ] || curl -sSfL \
      "http://deb.debian.org/debian/pool/main/l/lammps/lammps_${version}.orig.tar.xz" -o "$cache/lammps.tar.xz"
  [ -d "$cache/cmake" ] || tar xJf "$cache/lammps.tar.xz" -C "$cache" --strip-components=1
  cmake -S "$cache/cmake" -B "$cache/build" -DCMAKE_BUILD_TYPE=Release -DBUILD_MPI=off -DBUILD_OMP=on \
      -DPKG_OPENMP=on -DPKG_DPD-BASIC=on -DPKG_DPD-REACT=on -DPKG_MOLECULE=on > "$cache/configure.log"
  cmake --build "$cache/build" -j"$(nproc)" > "$cache/build.log"
fi
bash scripts/build.sh > /dev/null
PYTHONPATH="$PWD/build/python" /usr/bin/python3 -m openmmdpd.lammps_check --lmp "$lmp" "$@"
