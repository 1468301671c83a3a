#!/usr/bin/env bash
# Installs the Debian 12 packages lgvi-testbed builds and runs with. Idempotent: when every
# package is already installed it does nothing (no apt-get update, no network).
# Runs as root, or through sudo when that is available.
set -euo pipefail

packages=(
  g++ cmake make pkg-config git
  ninja-build            # the README commands' generator: compiles any target's files while others link
  libeigen3-dev          # fixed-size linear algebra
  libsundials-dev        # CVODE / CVODES baselines
  libgsl-dev             # GSL odeiv2 baselines, splines
  libboost-dev           # Boost.Odeint (header-only)
  libnlopt-cxx-dev       # SLSQP for the direct method
  coinor-libipopt-dev    # IPOPT: multiple shooting for the direct method (ocp --solver ipopt)
  libgtest-dev           # tests
  libbenchmark-dev       # Google Benchmark
  libcli11-dev           # command-line options
  libtomlplusplus-dev    # scene files (TOML)
  nlohmann-json3-dev     # reading JSON summaries back (validate, suite --check-against)
  python3-dev            # the Python module lgvi (python/): headers to build it against
  pybind11-dev           # the Python module's bindings
  python3-numpy          # its arrays, and the pytest suite's
  python3-pytest         # the Python tests (ctest python_tests)
  python3-nbclient       # executes the example notebook in a Jupyter kernel (ctest notebook_quick_start)
  python3-nbformat       # reads and validates it
  python3-ipykernel      # the kernel
  gnuplot-nox            # plots (pngcairo)
  fonts-dejavu-core      # a font for the PNG plots (not pulled in without recommends)
  clang                  # tests/sanitize.sh: the ASan+UBSan build and the libFuzzer target
  libclang-rt-14-dev     # clang's sanitizer and libFuzzer runtimes (only recommended by clang)
  slurmctld slurmd slurm-client munge  # tests/slurm: a single-node SLURM runs a sharded study
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
[ ${#missing[@]} -eq 0 ] && exit 0

echo "install-deps: installing ${missing[*]}" >&2
as_root=()
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "install-deps: run as root (or install sudo)" >&2; exit 1; }
  as_root=(sudo)
fi
export DEBIAN_FRONTEND=noninteractive
"${as_root[@]}" apt-get update -q
"${as_root[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}"
