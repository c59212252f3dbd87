#!/usr/bin/env bash
# Installs motionblocks' build and test dependencies from Debian's packages (Debian 12).
# Idempotent: packages already present are skipped, so a second run costs only a dpkg query.
set -euo pipefail

PACKAGES=(
  build-essential cmake pkg-config
  ccache                   # compiler cache (the presets' compiler launcher)
  mold                     # fast linker (CMakeLists.txt uses it when found)
  libeigen3-dev            # linear algebra
  libsundials-dev          # CVODE
  libboost-dev libboost-graph-dev  # Boost.Graph (header-only parts), Boost.Math
  nlohmann-json3-dev       # diagrams, model files
  libgtest-dev libgmock-dev libbenchmark-dev
  libcli11-dev libfmt-dev  # command line, formatting
  libnlopt-cxx-dev         # L-BFGS with bounds for MAP fits
  libtbb-dev               # parallel sweeps
  libopenmpi-dev openmpi-bin  # sweep --mpi (optional: built only when found; its test runs mpirun)
  gnuplot-nox              # report figures
  graphviz                 # motionblocks draw and the reports' diagrams (dot)
  libjs-dygraphs           # the reports' interactive charts: dygraph.min.js, read and embedded when a report is written
  chromium                 # tests/browser: the reports opened in headless Chromium (make test)
  libvalijson-dev          # JSON Schema validation of diagrams and sweeps
  clang libclang-rt-14-dev # libFuzzer (the fuzz preset: fuzzers of the file readers)
  pybind11-dev python3-dev # the motionblocks Python module (python/)
  python3-numpy python3-pandas python3-pytest  # its arrays, DataFrames (to_pandas) and tests (make test)
)

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#PACKAGES[@]} packages present"
  exit 0
fi
echo "install-deps: installing ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
