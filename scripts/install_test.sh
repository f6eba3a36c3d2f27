#!/usr/bin/env bash
# Installs the build in build/ (or $1) into a temporary prefix with `cmake --install`, then
# (a) builds a C++ program with find_package(OpenMMDPD) against that prefix and runs one step,
# (b) runs the README's quick start (made small) with /usr/bin/python3 in an environment that
#     holds only PATH and the PYTHONPATH the install docs name.
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir="${1:-build}"
prefix=$(mktemp -d)
trap 'rm -rf "$prefix"' EXIT
cmake --install "$build_dir" --prefix "$prefix" > "$prefix/install.log"

cmake -S tests/install -B "$prefix/example" -DCMAKE_PREFIX_PATH="$prefix" > "$prefix/example.log"
cmake --build "$prefix/example" >> "$prefix/example.log"
"$prefix/example/one_step"

site_packages=$(dirname "$(find "$prefix" -type d -name openmmdpd -path "*-packages/*" | head -1)")
quick_start="$prefix/quick_start.py"
awk '/^```python/{on=1; next} /^```/{if (on) exit} on' README.md |
  sed -e 's/num_particles=4000/num_particles=500/' -e 's/simulation.step(10000)/simulation.step(200)/' > "$quick_start"
(cd "$prefix" && env -i PATH=/usr/bin:/bin PYTHONPATH="$site_packages" /usr/bin/python3 "$quick_start")
echo "install test: C++ and Python from $prefix passed"
