#!/usr/bin/env bash
# Peak memory and wall time of `graftnav navigate` (ekf, rts, fgo-window, fgo) and `graftnav
# diagnose` against the length of a generated 200 Hz recording (docs/BENCHMARKS.md, "Memory
# against recording length"). A benchmark, not a test: it takes minutes.
#
# Usage: scripts/dev/bench_memory.sh OUT_DIR [GRAFTNAV]      (GRAFTNAV default: build/graftnav)
# Environment: LENGTHS_MIN (default "15 30 60 120 480"), RUNS (runs per measurement, the median
# is reported; default 1), ESTIMATORS (default "ekf rts fgo-window fgo"), DIAGNOSE (1: also
# diagnose, default 1), DIAGNOSE_MAX_MIN (diagnose only lengths up to this many minutes; default
# 480: past binning diagnose holds the reference record, the bins and the candidate library,
# ~270 MB per hour), MAX_SIM_RSS_MB (skip a length
# whose simulation is predicted, linearly from the longest one done, to need more; default 4000:
# the simulator streams the field IMUs of this case, so the prediction is an upper bound).
#
# Each length is a motion-script drive (60 s at rest, then 100 s straights and 90-degree turns at
# 10 m/s) simulated with the POS1100-like tested IMU of mems_57min.yaml, 1 Hz GNSS, truth at
# 10 Hz and a short lab session. `navigate` runs on a copy of the case without truth.nav (the
# initial state from case.yaml, no errors computed: the solution alone, as the peers' runs), with
# 60 s outages every 180 s. Peak RSS, CPU time (user + system) and wall time come from
# /usr/bin/time -v; on a shared machine the CPU time is the one to compare. Writes
# OUT_DIR/memory.tsv and OUT_DIR/memory.md (the table for docs/BENCHMARKS.md).
set -euo pipefail
[ $# -ge 1 ] || { sed -n '2,18p' "$0"; exit 2; }
out="$1"
repo="$(cd "$(dirname "$0")/../.." && pwd)"
here="$(cd "$(dirname "$0")" && pwd)"
bin="$(realpath "${2:-$repo/build/graftnav}")"
lengths="${LENGTHS_MIN:-15 30 60 120 480}"
runs="${RUNS:-1}"
estimators="${ESTIMATORS:-ekf rts fgo-window fgo}"
diagnose="${DIAGNOSE:-1}"
max_sim_mb="${MAX_SIM_RSS_MB:-4000}"
diagnose_max_min="${DIAGNOSE_MAX_MIN:-480}"
[ -x "$bin" ] || { echo "bench_memory.sh: no executable $bin" >&2; exit 1; }
[ -x /usr/bin/time ] || { echo "bench_memory.sh: needs /usr/bin/time (package time)" >&2; exit 1; }
mkdir -p "$out/cases" "$out/runs"
tsv="$out/memory.tsv"
printf "length_min\tsamples\twhat\tpeak_rss_MB\tcpu_s\twall_s\n" > "$tsv"

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

sim_mb_per_min=0
for L in $lengths; do
  case_dir="$out/cases/bench_${L}min"
  if [ ! -f "$case_dir/field/tested_imu.txt" ]; then
    predicted=$(awk -v a="$sim_mb_per_min" -v l="$L" 'BEGIN {printf "%d", a * l}')
    if [ "$predicted" -gt "$max_sim_mb" ]; then
      echo "bench_memory.sh: skipping $L min: the simulation would need ~$predicted MB (> MAX_SIM_RSS_MB=$max_sim_mb)" >&2
      printf "%s\t-\tsimulate (skipped, predicted %s MB)\t-\t-\t-\n" "$L" "$predicted" >> "$tsv"
      continue
    fi
    sim_config "$L" "$out/cases/bench_${L}min.yaml"
    read -r rss cpu wall < <(runs=1 measure simulate "$out/runs/sim_${L}.log" -- \
        "$bin" simulate --sim-config "$out/cases/bench_${L}min.yaml" --out "$case_dir")
    echo "$rss $cpu $wall" > "$case_dir.sim"
    sim_mb_per_min=$(awk -v r="$rss" -v l="$L" -v a="$sim_mb_per_min" 'BEGIN {x = r / l; print (x > a ? x : a)}')
    printf "%s\t-\tsimulate\t%s\t%s\t%s\n" "$L" "$rss" "$cpu" "$wall" >> "$tsv"
  fi
  if [ -f "$case_dir.sim" ] && ! grep -q "^$L	-	simulate	" "$tsv"; then  # a case made by an earlier run
    read -r rss cpu wall < "$case_dir.sim"
    sim_mb_per_min=$(awk -v r="$rss" -v l="$L" -v a="$sim_mb_per_min" 'BEGIN {x = r / l; print (x > a ? x : a)}')
    printf "%s\t-\tsimulate\t%s\t%s\t%s\n" "$L" "$rss" "$cpu" "$wall" >> "$tsv"
  fi
  nav_case="$case_dir.nav"  # the case without truth.nav
  mkdir -p "$nav_case/field"
  cp "$case_dir/case.yaml" "$nav_case/"
  for f in gnss.pos gnss_fixtype.txt tested_imu.txt; do
    [ -e "$case_dir/field/$f" ] && ln -sf "$(realpath "$case_dir/field/$f")" "$nav_case/field/$f"
  done
  samples=$(wc -l < "$case_dir/field/tested_imu.txt")
  for est in $estimators; do
    read -r rss cpu wall < <(measure "navigate $est $L min" "$out/runs/${est}_${L}.log" -- \
        "$bin" navigate "$nav_case" --imu tested --estimator "$est" --outage-length 60 \
        --outage-period 180 --out "$out/runs/${est}_${L}" --no-plots)
    printf "%s\t%s\tnavigate --estimator %s\t%s\t%s\t%s\n" "$L" "$samples" "$est" "$rss" "$cpu" "$wall" >> "$tsv"
    echo "$L min $est: $rss MB, CPU $cpu s, wall $wall s" >&2
  done
  if [ "$diagnose" = 1 ] && [ "$L" -gt "$diagnose_max_min" ]; then
    printf "%s\t%s\tdiagnose (skipped, above DIAGNOSE_MAX_MIN=%s)\t-\t-\t-\n" "$L" "$samples" "$diagnose_max_min" >> "$tsv"
  elif [ "$diagnose" = 1 ]; then
    read -r rss cpu wall < <(measure "diagnose $L min" "$out/runs/diagnose_${L}.log" -- \
        "$bin" diagnose "$case_dir" --out "$out/runs/diagnose_${L}" --no-plots)
    printf "%s\t%s\tdiagnose\t%s\t%s\t%s\n" "$L" "$samples" "$rss" "$cpu" "$wall" >> "$tsv"
    echo "$L min diagnose: $rss MB, CPU $cpu s, wall $wall s" >&2
  fi
done

python3 "$here/bench_memory_table.py" "$tsv" "$out/memory.md"
