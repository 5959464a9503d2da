#!/usr/bin/env bash
# Writes the mismatch finder's result tables on simulated cases into docs/results/ from the
# current binary (do not edit those files by hand):
#   docs/results/mismatch_concealed.md         the concealed-effects suite, one seed per case
#                                              (configs/sim/concealed/*.yaml, EKF navigation
#                                              level), and `graftnav diagnose` on the bundled
#                                              samples (data/sample_*).
#   docs/results/mismatch_concealed_seeds.md   with --seeds N: the Monte-Carlo tables over N seeds
#                                              per case (detection, parameters, DIFF of mean ERR).
# The runs themselves are scripts/experiments/run_concealed_suite.sh; this script adds the header (commit,
# command, machine, wall time) and the samples.
#
# Usage: scripts/experiments/mismatch_results_tables.sh [--seeds N] [--jobs J] [--work DIR] [--binary BIN]
#   --seeds N  Monte Carlo instead of the single-seed suite (18 cases x N seeds; about 2-6 min
#              per seed on two shared cores, so --seeds 20 takes one to two hours).
#   --jobs J   cases run in parallel (default 2).
#   --work     where the cases and diagnoses go (default /tmp/graftnav_mismatch_results).
#   --binary   the graftnav binary (default build/graftnav).
# Single-seed run: 2-6 min on two shared cores (126 s and 314 s measured, depending on the load).
set -euo pipefail
repo="$(cd "$(dirname "$0")/../.." && pwd)"
here="$(cd "$(dirname "$0")" && pwd)"
seeds=0
jobs=2
work=/tmp/graftnav_mismatch_results
bin="$repo/build/graftnav"
while [ $# -gt 0 ]; do
  case "$1" in
    --seeds) seeds="$2"; shift 2 ;;
    --jobs) jobs="$2"; shift 2 ;;
    --work) work="$2"; shift 2 ;;
    --binary) bin="$(realpath "$2")"; shift 2 ;;
    -h|--help) sed -n '2,19p' "$0"; exit 0 ;;
    *) echo "unknown option $1" >&2; exit 2 ;;
  esac
done
py="${GRAFTNAV_PYTHON:-/usr/bin/python3}"
[ -x "$py" ] || py=python3
commit="$(git -C "$repo" rev-parse --short HEAD)"
dirty=""
git -C "$repo" diff --quiet HEAD -- core apps filters graph || dirty=" (with uncommitted changes)"
machine="$(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ *//')"
mkdir -p "$work" "$repo/docs/results"

header() {  # title, command
  echo "# $1"
  echo
  echo "Written by \`scripts/experiments/mismatch_results_tables.sh\` (do not edit by hand) from the code at"
  echo "commit $commit$dirty. Machine: $machine, shared."
  echo
  echo "Command: \`$2\`"
  echo
}

start=$(date +%s)
if [ "$seeds" -gt 0 ]; then
  doc="$repo/docs/results/mismatch_concealed_seeds.md"
  tables="$work/tables.md"
  for k in $(seq 1 "$seeds"); do
    nice -n 5 "$repo/scripts/experiments/run_concealed_suite.sh" --jobs "$jobs" --seeds "$k" --first-seed "$k" \
      "$work" "$bin" > /dev/null
  done
  "$repo/scripts/experiments/run_concealed_suite.sh" --score-only --seeds "$seeds" "$work" "$bin" > "$tables"
  {
    header "Mismatch finder: concealed-effects suite over $seeds seeds per case" \
      "scripts/experiments/mismatch_results_tables.sh --seeds $seeds"
    echo "Seeds YAML seed + 1000 k, k = 1..$seeds; independent lab and field noise; EKF navigation"
    echo "level; outages of 60 s every 120 s from 100 s. Wall time $(( ($(date +%s) - start) / 60 )) min."
    echo
    cat "$tables"
  } > "$doc"
  echo "wrote $doc"
  exit 0
fi

doc="$repo/docs/results/mismatch_concealed.md"
tables="$work/tables.md"
nice -n 5 "$repo/scripts/experiments/run_concealed_suite.sh" --jobs "$jobs" "$work" "$bin" > "$tables"
for grade in mems tactical; do
  "$bin" diagnose "$repo/data/sample_$grade" --out "$work/sample_${grade}_diag" --no-plots \
    > "$work/sample_$grade.diagnose.log" 2>&1
done
elapsed=$(( $(date +%s) - start ))
{
  header "Mismatch finder: concealed-effects suite, one seed per case" \
    "scripts/experiments/mismatch_results_tables.sh"
  echo "Each case (configs/sim/concealed/*.yaml, its YAML seed) is simulated and diagnosed with"
  echo "\`graftnav diagnose CASE --out OUT --no-plots --estimator ekf --outage-length 60"
  echo "--outage-period 120 --outage-start 100\` (scripts/experiments/run_concealed_suite.sh, which also defines"
  echo "the scoring: a claim not injected is a false claim; a parameter is within when within 3 sigma"
  echo "or 20 %; a miss states its truth / detection-limit ratio). Wall time of this run, samples"
  echo "included: $elapsed s."
  echo
  echo "## Concealed-effects suite"
  echo
  cat "$tables"
  echo
  echo "## Bundled samples"
  echo
  echo "\`graftnav diagnose data/sample_GRADE --out OUT --no-plots\`: the tested IMU carries only terms"
  echo "that grafting models, so nothing should be claimed."
  echo
  "$py" "$here/mismatch_samples_table.py" "$work"
} > "$doc"
echo "wrote $doc"
