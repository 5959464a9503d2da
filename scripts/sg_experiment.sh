#!/usr/bin/env bash
# Issue 6 verification on the 57-minute real track: simulate tactical and MEMS cases (errors of
# the kinds grafting models only, and with Gauss-Markov bias wander), then evaluate SG#1/SG#2
# against the simulated real IMU with the EKF and the batch factor graph.
#   bash scripts/sg_experiment.sh [OUT_DIR] [SEEDS...]    (default out/sg_experiment, seed 1)
# Needs ./build/graftnav (scripts/setup.sh). About 2 minutes per seed on 2 cores.
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=${1:-out/sg_experiment}
shift || true
SEEDS=("${@:-1}")
mkdir -p "$OUT/cases"
cases=()
for seed in "${SEEDS[@]}"; do
  for cfg in configs/sg/tactical_modelled.yaml configs/sg/mems_modelled.yaml \
             configs/sim/tactical_57min.yaml configs/sim/mems_57min.yaml; do
    name=$(basename "$cfg" .yaml)_seed${seed}
    [[ -f "$OUT/cases/$name/case.yaml" ]] || ./build/graftnav simulate --config "$cfg" --out "$OUT/cases/$name" --seed "$seed" > /dev/null
    cases+=("$(realpath "$OUT/cases/$name")")
  done
done
{
  echo "out: $(realpath "$OUT")/runs"
  echo "jobs: 0"
  echo "plots: true"
  echo "cases: [$(IFS=,; echo "${cases[*]}")]"
  echo "estimators: [ekf, fgo]"
  echo "outage_schedules:"
  echo "  - {length_s: 60, period_s: 180, start_s: 300}"
} > "$OUT/manifest.yaml"
./build/graftnav batch "$OUT/manifest.yaml"
echo "summary: $OUT/runs/summary.md"
