#!/usr/bin/env bash
# Installs the Debian packages graftnav needs (only those missing), then configures (Release)
# and builds into ./build. Safe to run again; used by the README commands and by .ci/run.
# munge and slurm-wlm are for the batch test on a localhost Slurm cluster (docs/batch.md).
set -euo pipefail
cd "$(dirname "$0")/.."

PACKAGES=(build-essential cmake ninja-build ccache pkg-config
  libeigen3-dev libceres-dev libsuitesparse-dev libgeographiclib-dev libyaml-cpp-dev
  libgtest-dev libgmock-dev libbenchmark-dev libcli11-dev libfmt-dev nlohmann-json3-dev
  python3 python3-matplotlib dpkg-dev
  pybind11-dev python3-dev python3-numpy python3-yaml  # the Python module (docs/python.md)
  python3-pandas python3-pytest  # optional for the module: results() as DataFrames; pytest
  libsqlite3-dev sqlite3 munge slurm-wlm
  time  # time: /usr/bin/time -v for scripts/dev/bench_memory.sh
  clang-format-14 universal-ctags)  # scripts/dev/check_format.sh, scripts/dev/check_sizes.sh

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep "install ok installed" >/dev/null || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}"
  SUDO=""
  [[ $(id -u) -ne 0 ]] && SUDO="sudo"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

JOBS=$(nproc)
# ccache keys on paths relative to the checkout, so a fresh clone elsewhere reuses the cache.
export CCACHE_BASEDIR="$PWD"
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build build -j "$JOBS"
