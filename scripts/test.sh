#!/usr/bin/env bash
# Installs what is missing, builds (Release) and runs every test under CTest.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
ctest --test-dir build --output-on-failure -j "$(nproc)"
