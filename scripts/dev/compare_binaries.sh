#!/usr/bin/env bash
# Runs two graftnav binaries on the same inputs and compares their JSON results number by number
# (scripts/dev/compare_outputs.py): evaluate, navigate, real (four estimators, 30-s outages every
# 120 s) and diagnose on the bundled samples, and diagnose on the concealed suite's single-seed
# cases with --concealed. Used to show that a refactoring leaves the results unchanged.
#
# Usage: scripts/dev/compare_binaries.sh BINARY_A BINARY_B OUT_DIR [--concealed] [--rtol R]
set -euo pipefail
repo="$(cd "$(dirname "$0")/../.." && pwd)"
a="$(realpath "$1")"; b="$(realpath "$2")"; out="$3"; shift 3
concealed=0; rtol=1e-12
while [ $# -gt 0 ]; do
  case "$1" in
    --concealed) concealed=1; shift ;;
    --rtol) rtol="$2"; shift 2 ;;
    *) echo "unknown option $1" >&2; exit 2 ;;
  esac
done
mkdir -p "$out"
run_both() {  # name, then the arguments after the binary with OUT standing for the output folder
  local name="$1"; shift
  for side in A B; do
    local bin="$a"; [ "$side" = B ] && bin="$b"
    local args=("${@//OUT/$out/$side/$name}")
    "$bin" "${args[@]}" > "$out/$side/$name.log" 2>&1 || { echo "$side $name failed (see $out/$side/$name.log)"; exit 1; }
  done
}
mkdir -p "$out/A" "$out/B"
printf "outages: {length_s: 30, period_s: 120, start_s: 100}\n" > "$out/real_run.yaml"
for grade in tactical mems; do
  case_dir="$repo/data/sample_$grade"
  run_both "evaluate_$grade" evaluate "$case_dir" --out OUT --run-config "$repo/configs/evaluate_sample.yaml" --no-plots
  run_both "navigate_$grade" navigate "$case_dir" --out OUT --imu tested --no-plots
  run_both "real_$grade" real "$case_dir" --out OUT --imu tested --run-config "$out/real_run.yaml" \
    --estimator ekf,rts,fgo,fgo-window --no-plots
  run_both "diagnose_$grade" diagnose "$case_dir" --out OUT --no-plots
done
if [ "$concealed" = 1 ]; then
  for cfg in "$repo"/configs/sim/concealed/*.yaml; do
    name="$(basename "$cfg" .yaml)"
    [ -d "$out/cases/$name" ] || "$a" simulate --sim-config "$cfg" --out "$out/cases/$name" > /dev/null
    run_both "concealed_$name" diagnose "$out/cases/$name" --out OUT --no-plots
  done
fi
python3 "$repo/scripts/dev/compare_outputs.py" "$out/A" "$out/B" --rtol "$rtol"
