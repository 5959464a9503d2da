#!/usr/bin/env bash
# Timed run of `graftnav evaluate` with the default K (20 realizations per SG strategy) on the
# 57-minute 200 Hz tactical case (configs/sim/tactical_57min.yaml, about 1 h of driving, 17
# outages of 60 s), EKF, for docs/BENCHMARKS.md. Prints wall time, CPU time and peak RSS.
# Usage: scripts/dev/bench_evaluate.sh [WORK_DIR] [GRAFTNAV]   (defaults /tmp/graftnav_bench, build/graftnav)
set -euo pipefail
repo="$(cd "$(dirname "$0")/../.." && pwd)"
work="${1:-/tmp/graftnav_bench}"
bin="$(realpath "${2:-$repo/build/graftnav}")"
case_dir="$work/tactical_57min"
[ -f "$case_dir/case.yaml" ] || "$bin" simulate --sim-config "$repo/configs/sim/tactical_57min.yaml" --out "$case_dir" > /dev/null
rm -rf "$work/eval"
/usr/bin/time -f "wall %e s, user %U s, sys %S s, peak RSS %M kB" \
  "$bin" evaluate "$case_dir" --out "$work/eval" --estimator ekf --no-plots 2> "$work/eval.log" > "$work/eval.out"
grep -E 'navigating|navigated|wall' "$work/eval.log"
nproc; grep -m1 'model name' /proc/cpuinfo
