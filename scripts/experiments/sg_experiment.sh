#!/usr/bin/env bash
# SG verification on the 57-minute real track: simulate tactical and MEMS cases (errors of
# the kinds grafting models only, and with Gauss-Markov bias wander), then evaluate SG#1/SG#2
# against the simulated real IMU with the EKF and the batch factor graph.
#   bash scripts/experiments/sg_experiment.sh [OUT_DIR] [SEEDS...]    (default out/sg_experiment, seed 1)
# Needs ./build/graftnav (scripts/setup.sh). About 4-5 minutes per seed on 2 cores; ~430 MB of
# simulated case per configuration and seed (6 per seed).
set -euo pipefail
cd "$(dirname "$0")/../.."
OUT=${1:-out/sg_experiment}
shift || true
SEEDS=("${@:-1}")
mkdir -p "$OUT/cases"
# Two designs:
#  - independent: the lab records are another realization of the sensor noise (as a real IMU on
#    another day); DIFF of one run mixes grafting errors with the spread of two realizations.
#  - crn (common random numbers): the lab static record carries the field noise stream and the
#    graft starts at lab sample 0 (configs/sg/crn_run.yaml), so SG and REAL share one realization
#    and DIFF measures what grafting models or misses. Only for the "modelled" cases.
cases=()
crn_cases=()
for seed in "${SEEDS[@]}"; do
  for cfg in configs/sg/tactical_modelled.yaml configs/sg/mems_modelled.yaml \
             configs/sim/tactical_57min.yaml configs/sim/mems_57min.yaml; do
    name=$(basename "$cfg" .yaml)_seed${seed}
    [[ -f "$OUT/cases/$name/case.yaml" ]] || ./build/graftnav simulate --sim-config "$cfg" --out "$OUT/cases/$name" --seed "$seed" > /dev/null
    cases+=("$(realpath "$OUT/cases/$name")")
  done
  for cfg in configs/sg/tactical_modelled.yaml configs/sg/mems_modelled.yaml; do
    name=$(basename "$cfg" .yaml)_crn_seed${seed}
    [[ -f "$OUT/cases/$name/case.yaml" ]] || ./build/graftnav simulate --sim-config "$cfg" --out "$OUT/cases/$name" --seed "$seed" --common-random-numbers > /dev/null
    crn_cases+=("$(realpath "$OUT/cases/$name")")
  done
done
manifest() {  # OUT_SUBDIR RUN_CONFIG CASES...
  local sub=$1 config=$2
  shift 2
  echo "out: $(realpath "$OUT")/$sub"
  echo "jobs: 0"
  echo "plots: true"
  [[ -n "$config" ]] && echo "config: $(realpath "$config")"
  echo "cases: [$(IFS=,; echo "$*")]"
  echo "estimators: [ekf, fgo]"
  echo "outage_schedules:"
  echo "  - {length_s: 60, period_s: 180, start_s: 300}"
}
manifest runs configs/sg/single_realization_run.yaml "${cases[@]}" > "$OUT/manifest.yaml"
manifest runs_crn configs/sg/crn_run.yaml "${crn_cases[@]}" > "$OUT/manifest_crn.yaml"
./build/graftnav batch "$OUT/manifest.yaml"
./build/graftnav batch "$OUT/manifest_crn.yaml"
echo "summary: $OUT/runs/summary_monte_carlo.md and $OUT/runs_crn/summary_monte_carlo.md"
