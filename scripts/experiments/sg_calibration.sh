#!/usr/bin/env bash
# Calibration of the predictive intervals of `graftnav evaluate` (docs/sg-evaluation.md): for each
# case config, simulate N seeds (independent lab and field noise), evaluate each with K grafted
# realizations, and tabulate how often ERR_REAL falls inside SG#1's and SG#2's 90 % intervals.
# On the null cases (no physics that grafting lacks) SG#2 must cover REAL in 80-97 % of seeds on
# every statistic; on cases with a concealed dynamic effect the table shows where SG#1 misses.
#
# Usage: scripts/experiments/sg_calibration.sh [--seeds N] [--realizations K] [--jobs J] [--estimator E]
#                                  [--cases "cfg.yaml ..."] [--run-config FILE] [--table FILE]
#                                  OUT_DIR [GRAFTNAV]
#   --seeds N       seeds per case (default 20); simulate --seed 5000+s, evaluate --seed s
#   --realizations  K per SG strategy (default 20)
#   --jobs J        evaluations in parallel (default 2), each navigating on one thread
#   --cases         case configs (default: configs/sim/calibration/{null_tactical,null_mems,
#                   axis_misalignment_mems,gsens_mems}.yaml)
#   --run-config    evaluate's run config (default configs/sg/calibration_run.yaml;
#                   configs/sg/calibration_run_aided.yaml adds the odometer and NHC)
#   --table FILE    also write the Markdown tables to FILE (e.g. docs/results/sg-calibration.md)
#   --inject DOC    and replace the sg_calibration block of DOC (docs/sg-evaluation.md) with them
# The simulated cases are deleted after their evaluation; OUT_DIR/runs/<case>_s<seed>/ keeps
# evaluation.json and tables.md.
set -euo pipefail
repo="$(cd "$(dirname "$0")/../.." && pwd)"
seeds=20; K=20; jobs=2; estimator=ekf; table=""; inject=""
run_config="$repo/configs/sg/calibration_run.yaml"
default_cases="$repo/configs/sim/calibration/null_tactical.yaml $repo/configs/sim/calibration/null_mems.yaml $repo/configs/sim/calibration/axis_misalignment_mems.yaml $repo/configs/sim/calibration/gsens_mems.yaml"
cases="$default_cases"
pos=()
while [ $# -gt 0 ]; do
  case "$1" in
    --seeds) seeds="$2"; shift 2 ;;
    --realizations) K="$2"; shift 2 ;;
    --jobs) jobs="$2"; shift 2 ;;
    --estimator) estimator="$2"; shift 2 ;;
    --cases) cases="$2"; shift 2 ;;
    --run-config) run_config="$(realpath "$2")"; shift 2 ;;
    --table) table="$2"; shift 2 ;;
    --inject) inject="$2"; shift 2 ;;
    -h|--help) sed -n '2,21p' "$0"; exit 0 ;;
    --*) echo "sg_calibration: unknown option $1" >&2; exit 2 ;;
    *) pos+=("$1"); shift ;;
  esac
done
[ ${#pos[@]} -ge 1 ] || { echo "usage: scripts/experiments/sg_calibration.sh [options] OUT_DIR [GRAFTNAV]" >&2; exit 2; }
out="$(mkdir -p "${pos[0]}" && cd "${pos[0]}" && pwd)"
bin="$(realpath "${pos[1]:-$repo/build/graftnav}")"
mkdir -p "$out/runs" "$out/cases" "$out/logs"

run_one() {  # config seed
  local cfg="$1" s="$2" name
  name="$(basename "$cfg" .yaml)_s$s"
  [ -f "$out/runs/$name/evaluation.json" ] && return 0
  "$bin" simulate --sim-config "$cfg" --out "$out/cases/$name" --seed $((5000 + s)) > "$out/logs/$name.sim.log" 2>&1
  "$bin" evaluate "$out/cases/$name" --out "$out/runs/$name" --run-config "$run_config" \
    --estimator "$estimator" --realizations "$K" --seed "$s" --jobs 1 --no-plots > "$out/logs/$name.eval.log" 2>&1
  rm -rf "$out/cases/$name" "$out/runs/$name"/IMU_SG*.txt "$out/runs/$name"/errors_*.csv
  echo "sg_calibration: $name done"
}
export -f run_one
export out bin repo estimator K run_config
start=$(date +%s)
# Seed-major order: an interrupted run still has every case on the first seeds.
for s in $(seq 1 "$seeds"); do for cfg in $cases; do echo "$cfg $s"; done; done |
  xargs -P "$jobs" -L 1 bash -c 'run_one "$0" "$1"'
echo "sg_calibration: $(( $(date +%s) - start )) s for $(ls "$out/runs" | wc -l) runs"
rc_flag=""
[ "$run_config" = "$repo/configs/sg/calibration_run.yaml" ] || rc_flag=" --run-config ${run_config#"$repo"/}"
[ "$cases" = "$default_cases" ] || rc_flag="$rc_flag --cases \"${cases//"$repo"\//}\""
/usr/bin/python3 "$repo/scripts/experiments/sg_calibration_table.py" "$out/runs" --estimator "$estimator" \
  --command "scripts/experiments/sg_calibration.sh --seeds $seeds --realizations $K --estimator $estimator${rc_flag} OUT" ${table:+--out "$table"} ${inject:+--inject "$inject"}
