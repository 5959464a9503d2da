#!/usr/bin/env bash
# Concealed-effects suite of the mismatch finder (docs/mismatch.md): for every
# configs/sim/concealed/*.yaml, simulate the case, run `graftnav diagnose` with a navigation
# estimator, and print a Markdown table: effect injected, effect found, parameter error, fit
# before/after (signal RMS and DIFF of the five outage statistics). A claimed scale_factor that is
# the reference IMU's own scale error as the simulator drew it (simulation.yaml, sign reversed,
# within 3 sigma or 20 %) is a real difference between the simulation, built on the reference
# signal, and the tested IMU: it is marked in the "found" column and not counted as a false claim.
#
# Usage: scripts/experiments/run_concealed_suite.sh [--seeds N] [--estimator ekf|rts|fgo] [--jobs J] [--crn]
#                                       [--cases "name1 name2"] [--config-dir DIR]
#                                       [OUT_DIR] [GRAFTNAV_BINARY]
#   OUT_DIR defaults to /tmp/graftnav_concealed; the binary to build/graftnav.
#   --seeds N   Monte-Carlo mode: every case is simulated with N seeds (`simulate --seed`, the
#               YAML seed + 1000 k, k = 1..N, so the single-seed run is not among them), each is
#               diagnosed, and the tables report per case the detection rate of each injected
#               effect, the false claims, the parameter errors pooled over seeds, and ERR of SG2,
#               SG3, REAL as means over seeds with the DIFF of those means (before = SG2, after =
#               SG3) next to the spread of the single-run DIFF. Results under OUT_DIR/mc_<estimator>;
#               the simulated case directories and the diagnose's large files are deleted after
#               each run (KEEP_CASES=1 keeps them).
#   --first-seed K  with --seeds N: run k = K..N only (default 1); the tables cover every run
#               under OUT_DIR, so seeds run in batches (k outer, cases inner) add up.
#   --estimator ekf (default), rts or fgo.
#   --jobs J    cases run in parallel (default 1; the machine may be shared).
#   --cases     only these cases (YAML base names).
#   --score-only  no runs: tabulate the diagnoses already under OUT_DIR.
#   --config-dir  the case configs (default configs/sim/concealed; e.g. the output of
#               scripts/experiments/make_random_cases.sh).
#   --crn       common random numbers: simulate with --common-random-numbers (the lab session
#               carries the field tested IMU's noise stream) and diagnose with
#               configs/sg/crn_run.yaml (graft from lab sample 0), so SG2/SG3 and REAL share one
#               noise realization and DIFF measures the model, not two realizations
#               (docs/sg-evaluation.md). Results under OUT_DIR/crn (and OUT_DIR/crn/mc_<est>).
set -euo pipefail
repo="$(cd "$(dirname "$0")/../.." && pwd)"
here="$(cd "$(dirname "$0")" && pwd)"
seeds=0
first_seed=1
estimator=ekf
njobs=1
cases=""
crn=0
score_only=0
cfg_dir="$repo/configs/sim/concealed"
pos=()
while [ $# -gt 0 ]; do
  case "$1" in
    --seeds) seeds="$2"; shift 2 ;;
    --first-seed) first_seed="$2"; shift 2 ;;
    --estimator) estimator="$2"; shift 2 ;;
    --jobs) njobs="$2"; shift 2 ;;
    --cases) cases="$2"; shift 2 ;;
    --crn) crn=1; shift ;;
    --score-only) score_only=1; shift ;;
    --config-dir) cfg_dir="$(cd "$2" && pwd)"; shift 2 ;;
    -h|--help) sed -n '2,32p' "$0"; exit 0 ;;
    --*) echo "unknown option $1" >&2; exit 2 ;;
    *) pos+=("$1"); shift ;;
  esac
done
out="${pos[0]:-/tmp/graftnav_concealed}"
bin="${pos[1]:-$repo/build/graftnav}"
py="${GRAFTNAV_PYTHON:-/usr/bin/python3}"
[ -x "$py" ] || py=python3
[ "$crn" = 1 ] && out="$out/crn"
mkdir -p "$out"

cfgs=()
for cfg in "$cfg_dir"/*.yaml; do
  name="$(basename "$cfg" .yaml)"
  if [ -n "$cases" ] && [[ " $cases " != *" $name "* ]]; then continue; fi
  cfgs+=("$cfg")
done
[ ${#cfgs[@]} -gt 0 ] || { echo "no case selected" >&2; exit 2; }

# run_one CFG CASE_DIR DIAG_DIR [SEED]: simulate and diagnose one case; logs next to CASE_DIR.
run_one() {
  local cfg="$1" case_dir="$2" diag_dir="$3" seed="${4:-}"
  local seed_arg=() sim_crn=() diag_crn=()
  [ -n "$seed" ] && seed_arg=(--seed "$seed")
  if [ "$crn" = 1 ]; then
    sim_crn=(--common-random-numbers)
    diag_crn=(--run-config "$repo/configs/sg/crn_run.yaml")
  fi
  if ! "$bin" simulate --sim-config "$cfg" --out "$case_dir" "${seed_arg[@]}" "${sim_crn[@]}" > "$case_dir.simulate.log" 2>&1; then
    echo "simulate failed: $case_dir.simulate.log" >&2
    return 0
  fi
  round_as_text "$cfg" "$case_dir"
  "$bin" diagnose "$case_dir" --out "$diag_dir" --no-plots --estimator "$estimator" "${diag_crn[@]}" \
    --outage-length 60 --outage-period 120 --outage-start 100 > "$case_dir.diagnose.log" 2>&1 ||
    echo "diagnose failed: $case_dir.diagnose.log" >&2
  # The simulator's record of every error it drew (the reference IMU's too), for the scorer; kept
  # when the case directory is deleted.
  if [ -f "$case_dir/simulation.yaml" ] && [ -d "$diag_dir" ]; then
    cp "$case_dir/simulation.yaml" "$diag_dir/simulation.yaml" || true
  fi
}

# round_as_text CFG CASE_DIR: a case whose YAML has `text_decimals: {dtheta: D1, dvel: D2}` (read
# here; the simulator ignores the key with a warning) gets its field IMU files rewritten with D1
# and D2 fixed decimals for the angle and velocity increments, as a logger writes them (time
# column untouched). The lab files stay as simulated: SG#2 then carries no such lattice, which is
# the situation in which a text format's resolution used to be claimed as quantization.
round_as_text() {
  local cfg="$1" case_dir="$2" dec f tmp
  dec="$("$py" -c 'import sys, yaml
d = (yaml.safe_load(open(sys.argv[1])) or {}).get("text_decimals")
print("" if not d else "%d %d" % (int(d["dtheta"]), int(d["dvel"])))' "$cfg")"
  [ -n "$dec" ] || return 0
  set -- $dec
  for f in "$case_dir/field/tested_imu.txt" "$case_dir/field/ref_imu.txt"; do
    [ -f "$f" ] || continue
    tmp="$f.rounded"
    awk -v a="$1" -v v="$2" '{ printf "%s %.*f %.*f %.*f %.*f %.*f %.*f\n", $1, a, $2, a, $3, a, $4, v, $5, v, $6, v, $7 }' "$f" > "$tmp"
    mv "$tmp" "$f"
  done
}

# Waits until fewer than $njobs background runs are going.
throttle() {
  while [ "$(jobs -rp | wc -l)" -ge "$njobs" ]; do wait -n || true; done
}

if [ "$score_only" = 1 ]; then
  result_dir="$out"
  [ "$seeds" -eq 0 ] || result_dir="$out/mc_$estimator"
elif [ "$seeds" -eq 0 ]; then
  for cfg in "${cfgs[@]}"; do
    name="$(basename "$cfg" .yaml)"
    echo "== $name" >&2
    throttle
    run_one "$cfg" "$out/$name" "$out/${name}_diag" &
  done
  wait
  result_dir="$out"
else
  result_dir="$out/mc_$estimator"
  mkdir -p "$result_dir"
  for cfg in "${cfgs[@]}"; do
    name="$(basename "$cfg" .yaml)"
    base_seed="$("$py" -c 'import sys, yaml; print(int(yaml.safe_load(open(sys.argv[1]))["seed"]))' "$cfg")"
    mkdir -p "$result_dir/$name"
    for k in $(seq "$first_seed" "$seeds"); do
      s=$((base_seed + 1000 * k))
      echo "== $name seed $s" >&2
      throttle
      (
        run_one "$cfg" "$result_dir/$name/s$s" "$result_dir/$name/s${s}_diag" "$s"
        if [ "${KEEP_CASES:-0}" != 1 ]; then
          rm -rf "$result_dir/$name/s$s"
          rm -f "$result_dir/$name/s${s}_diag/IMU_SG3.txt" "$result_dir/$name/s${s}_diag/residual.csv"
        fi
      ) &
    done
  done
  wait
fi

"$py" "$here/concealed_suite_table.py" "$cfg_dir" "$result_dir" "$seeds" "$estimator" "${cfgs[@]}"
