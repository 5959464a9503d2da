#!/usr/bin/env bash
# Peak memory and CPU of `graftnav navigate` (each estimator), `compare`, `real`, `evaluate` and
# `diagnose` against the length of a generated 200 Hz recording with its 200 Hz truth.nav and a
# 1-h lab static record (docs/BENCHMARKS.md, "Memory against recording length"). A benchmark,
# not a test: it takes minutes to hours.
#
# Usage: scripts/dev/bench_memory.sh OUT_DIR [GRAFTNAV]      (GRAFTNAV default: build/graftnav)
# Environment: LENGTHS_MIN (default "15 60 480"), RUNS (runs per measurement, the median is
# reported; default 1), ESTIMATORS (default "ekf rts fgo-window fgo"), COMPARE_SETS (the
# estimator lists compare runs, default "ekf ekf,rts"), COMMANDS (default
# "navigate compare real evaluate diagnose"), CASES (folder of the simulated cases, default
# OUT_DIR/cases: another binary's run can share them), <COMMAND>_MAX_MIN (run that command only
# up to this many minutes; defaults: COMPARE 480, REAL 480, EVALUATE 480, DIAGNOSE 480),
# MAX_SIM_RSS_MB (skip a length whose simulation is predicted, linearly from the longest one
# done, to need more; default 4000), APPEND=1 (add the rows to an existing OUT_DIR/memory.tsv
# instead of starting it: a measurement split into runs by COMMANDS), DOC (a Markdown file whose
# "Memory against recording length" table is replaced by the measured one), NAVIGATE_RUN_CONFIG
# (a run config FILE: the navigate rows are measured with `--run-config FILE` instead, labelled
# with its name; the outages stay the command line's), NAVIGATE_RANGE_S ("A B": the navigate rows
# are measured again with --start A s after the IMU's first sample and --end B s before its last).
#
# Each length is a motion-script drive (60 s at rest, then 100 s straights and 90-degree turns at
# 10 m/s) simulated with the POS1100-like tested IMU of mems_57min.yaml, 1 Hz GNSS, truth at
# 200 Hz and a lab session with a 1-h static record. Every command runs on the whole case, its
# truth.nav beside it: navigate --imu tested with each estimator; compare with ekf and with
# ekf,rts (the filter-smoother cross-check); real with
# ekf (a run config with the same outages, written to OUT_DIR/real_run.yaml); evaluate with K = 20
# realizations per strategy on 2 workers (EKF); diagnose. Outages of 60 s every 180 s. Peak RSS,
# CPU time (user + system) and wall time come from /usr/bin/time -v; on a shared machine the CPU
# time is the one to compare. Writes OUT_DIR/memory.tsv and OUT_DIR/memory.md.
set -euo pipefail
[ $# -ge 1 ] || { sed -n '2,31p' "$0"; exit 2; }
out="$1"
repo="$(cd "$(dirname "$0")/../.." && pwd)"
here="$(cd "$(dirname "$0")" && pwd)"
bin="$(realpath "${2:-$repo/build/graftnav}")"
lengths="${LENGTHS_MIN:-15 60 480}"
runs="${RUNS:-1}"
estimators="${ESTIMATORS:-ekf rts fgo-window fgo}"
compare_sets="${COMPARE_SETS:-ekf ekf,rts}"
commands="${COMMANDS:-navigate compare real evaluate diagnose}"
max_sim_mb="${MAX_SIM_RSS_MB:-4000}"
cases="${CASES:-$out/cases}"
[ -x "$bin" ] || { echo "bench_memory.sh: no executable $bin" >&2; exit 1; }
[ -x /usr/bin/time ] || { echo "bench_memory.sh: needs /usr/bin/time (package time)" >&2; exit 1; }
mkdir -p "$cases" "$out/runs"
tsv="$out/memory.tsv"
if [ "${APPEND:-0}" != 1 ] || [ ! -f "$tsv" ]; then
  printf "length_min\tsamples\twhat\tpeak_rss_MB\tcpu_s\twall_s\n" > "$tsv"
fi

# sim_config MINUTES FILE: the motion-script case of that length.
sim_config() {
  python3 "$here/bench_memory_case.py" "$1" "$repo/configs/imu" > "$2"
}

# measure LABEL LOG -- COMMAND...: runs the command RUNS times under /usr/bin/time -v; prints
# "median_rss_MB median_cpu_s median_wall_s".
measure() {
  local label="$1" log="$2"; shift 3
  local rss=() cpu=() wall=()
  for ((r = 0; r < runs; r++)); do
    if ! /usr/bin/time -v "$@" > "$log" 2> "$log.time"; then
      echo "bench_memory.sh: $label failed, see $log and $log.time" >&2; exit 1
    fi
    rss+=("$(awk -F': ' '/Maximum resident set size/ {printf "%.1f", $2 / 1024}' "$log.time")")
    cpu+=("$(awk -F': ' '/User time|System time/ {s += $2} END {printf "%.2f", s}' "$log.time")")
    wall+=("$(awk -F': ' '/Elapsed \(wall clock\)/ {n = split($2, p, ":"); s = 0;
              for (i = 1; i <= n; i++) s = s * 60 + p[i]; printf "%.2f", s}' "$log.time")")
  done
  local mid=$(((runs + 1) / 2))
  printf "%s %s %s\n" "$(printf "%s\n" "${rss[@]}" | sort -g | sed -n "${mid}p")" \
    "$(printf "%s\n" "${cpu[@]}" | sort -g | sed -n "${mid}p")" "$(printf "%s\n" "${wall[@]}" | sort -g | sed -n "${mid}p")"
}

# row LENGTH WHAT RUN_NAME ARGS...: measures `graftnav ARGS` and appends its row.
row() {
  local L="$1" what="$2" name="$3"; shift 3
  read -r rss cpu wall < <(measure "$what $L min" "$out/runs/$name.log" -- "$bin" "$@")
  printf "%s\t%s\t%s\t%s\t%s\t%s\n" "$L" "$samples" "$what" "$rss" "$cpu" "$wall" >> "$tsv"
  echo "$L min $what: $rss MB, CPU $cpu s, wall $wall s" >&2
}

printf "outages:\n  length_s: 60\n  period_s: 180\n" > "$out/real_run.yaml"

sim_mb_per_min=0
for L in $lengths; do
  case_dir="$cases/bench_${L}min"
  if [ ! -f "$case_dir/field/tested_imu.txt" ]; then
    predicted=$(awk -v a="$sim_mb_per_min" -v l="$L" 'BEGIN {printf "%d", a * l}')
    if [ "$predicted" -gt "$max_sim_mb" ]; then
      echo "bench_memory.sh: skipping $L min: the simulation would need ~$predicted MB (> MAX_SIM_RSS_MB=$max_sim_mb)" >&2
      printf "%s\t-\tsimulate (skipped, predicted %s MB)\t-\t-\t-\n" "$L" "$predicted" >> "$tsv"
      continue
    fi
    sim_config "$L" "$cases/bench_${L}min.yaml"
    read -r rss cpu wall < <(runs=1 measure simulate "$out/runs/sim_${L}.log" -- \
        "$bin" simulate --sim-config "$cases/bench_${L}min.yaml" --out "$case_dir")
    echo "$rss $cpu $wall" > "$case_dir.sim"
    sim_mb_per_min=$(awk -v r="$rss" -v l="$L" -v a="$sim_mb_per_min" 'BEGIN {x = r / l; print (x > a ? x : a)}')
    printf "%s\t-\tsimulate\t%s\t%s\t%s\n" "$L" "$rss" "$cpu" "$wall" >> "$tsv"
  fi
  if [ -f "$case_dir.sim" ] && ! grep -q "^$L	-	simulate	" "$tsv"; then  # a case made by an earlier run
    read -r rss cpu wall < "$case_dir.sim"
    sim_mb_per_min=$(awk -v r="$rss" -v l="$L" -v a="$sim_mb_per_min" 'BEGIN {x = r / l; print (x > a ? x : a)}')
    printf "%s\t-\tsimulate\t%s\t%s\t%s\n" "$L" "$rss" "$cpu" "$wall" >> "$tsv"
  fi
  samples=$(wc -l < "$case_dir/field/tested_imu.txt")
  outages=(--outage-length 60 --outage-period 180)
  for cmd in $commands; do
    max_var="$(echo "$cmd" | tr a-z A-Z)_MAX_MIN"
    if [ "$cmd" != navigate ] && [ "$L" -gt "${!max_var:-480}" ]; then
      printf "%s\t%s\t%s (skipped, above %s=%s)\t-\t-\t-\n" "$L" "$samples" "$cmd" "$max_var" "${!max_var}" >> "$tsv"
      continue
    fi
    case "$cmd" in
      navigate)
        nav_config=() nav_label="" nav_tag=""
        if [ -n "${NAVIGATE_RUN_CONFIG:-}" ]; then
          nav_config=(--run-config "$(realpath "$NAVIGATE_RUN_CONFIG")")
          nav_label=" --run-config $(basename "$NAVIGATE_RUN_CONFIG")"
          nav_tag="_$(basename "$NAVIGATE_RUN_CONFIG" .yaml)"
        fi
        ranges=("")
        if [ -n "${NAVIGATE_RANGE_S:-}" ]; then
          read -r after before <<< "$NAVIGATE_RANGE_S"
          first=$(head -1 "$case_dir/field/tested_imu.txt" | awk '{print $1}')
          last=$(tail -1 "$case_dir/field/tested_imu.txt" | awk '{print $1}')
          ranges+=("$(awk -v f="$first" -v l="$last" -v a="$after" -v b="$before" \
            'BEGIN {printf "%.3f %.3f", f + a, l - b}')")
        fi
        for range in "${ranges[@]}"; do
          range_args=() range_label="" range_tag=""
          if [ -n "$range" ]; then
            read -r t0 t1 <<< "$range"
            range_args=(--start "$t0" --end "$t1")
            range_label=" --start +$after s --end -$before s"
            range_tag="_range"
          fi
          for est in $estimators; do
            name="${est}${nav_tag}${range_tag}_${L}"
            row "$L" "navigate --estimator $est$nav_label$range_label" "$name" navigate "$case_dir" \
                --imu tested --estimator "$est" "${outages[@]}" "${nav_config[@]}" "${range_args[@]}" \
                --out "$out/runs/$name" --no-plots
          done
        done ;;
      compare)
        for set in $compare_sets; do
          row "$L" "compare --estimator $set" "compare_${set/,/_}_${L}" compare "$case_dir" \
              --imu tested --estimator "$set" "${outages[@]}" --out "$out/runs/compare_${set/,/_}_${L}" \
              --no-plots
        done ;;
      real)
        row "$L" "real --estimator ekf" "real_${L}" real "$case_dir" --imu tested --estimator ekf \
            --run-config "$out/real_run.yaml" --out "$out/runs/real_${L}" --no-plots ;;
      evaluate)
        row "$L" "evaluate (K = 20, 2 workers)" "evaluate_${L}" evaluate "$case_dir" "${outages[@]}" \
            --jobs 2 --out "$out/runs/evaluate_${L}" --no-plots ;;
      diagnose)
        row "$L" "diagnose" "diagnose_${L}" diagnose "$case_dir" --out "$out/runs/diagnose_${L}" --no-plots ;;
      *) echo "bench_memory.sh: unknown command $cmd" >&2; exit 2 ;;
    esac
  done
done

python3 "$here/bench_memory_table.py" "$tsv" "$out/memory.md"
if [ -n "${DOC:-}" ]; then
  python3 "$here/bench_memory_table.py" --doc "$DOC" "$out/memory.md"
fi
