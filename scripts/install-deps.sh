#!/usr/bin/env bash
# Installs every Debian package semlb uses (idempotent); called by `make deps` and so by `.ci/run`.
set -euo pipefail
PACKAGES=(
  build-essential cmake make pkg-config git
  libopenmpi-dev openmpi-bin
  ocl-icd-opencl-dev opencl-headers pocl-opencl-icd clinfo
  libeigen3-dev libhdf5-dev hdf5-tools
  libcli11-dev libyaml-cpp-dev nlohmann-json3-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libtorch-dev
  libnlopt-cxx-dev   # semlb fit: the derivative-free search of learned_repartition's parameters
  python3 python3-matplotlib python3-h5py python3-numpy python3-scipy   # analysis/: fits and statistics (scipy.stats)
  python3-pygments   # analysis/provenance.py: source compared by its tokens (comments and layout aside)
  clang-format       # tests/test_format.sh: every C, C++ and OpenCL source as .clang-format lays it out
  python3-paraview   # tests/engine/io/test_paraview.sh opens the XDMF outputs with ParaView's default reader
  paraview xvfb   # tests/analysis/test_figures.sh renders the Day 0-5 ParaView state with pvbatch on a virtual display
  slurm-wlm munge    # tests/experiments/test_slurm.sh starts a single-node Slurm of its own
)
missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "deps: all ${#PACKAGES[@]} packages present"
  exit 0
fi
echo "deps: installing ${missing[*]}"
SUDO=""; [ "$(id -u)" -eq 0 ] || SUDO="sudo"
$SUDO apt-get update -q
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
