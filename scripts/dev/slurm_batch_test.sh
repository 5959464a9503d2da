#!/usr/bin/env bash
# The batch on a real Slurm: starts a one-node cluster on localhost (scripts/dev/slurm_local_cluster.sh),
# and for two manifests submits them as arrays (`graftnav batch --slurm --submit`, one array per
# command, two tasks per array element), waits for the arrays and the collect job, runs the same
# manifest locally and compares the summaries byte for byte:
#   1. the earlier manifest layout (one evaluate group: 2 samples x 2 seeds, one array);
#   2. configs/batch/workbench.yaml, a group of every command (real on two real drives with an
#      option axis, navigate, compare, evaluate on the samples, real-sg and diagnose): 16 tasks in
#      six arrays.
# Stops the daemons it started, by pid. Run by CTest (slurm_batch_localhost); needs root and the
# real recordings of ../shared, and FAILS when munge, slurm-wlm or the data are missing.
#
#   bash scripts/dev/slurm_batch_test.sh build/graftnav /tmp/slurm_batch
set -euo pipefail
if (($# != 2)); then
  echo "usage: $0 GRAFTNAV_BINARY WORK_DIR" >&2
  exit 2
fi
repo=$(cd "$(dirname "$0")/../.." && pwd)
exe=$(realpath "$1")
work=$2
rm -rf "$work"
mkdir -p "$work"
work=$(cd "$work" && pwd)

# shellcheck source=scripts/dev/slurm_local_cluster.sh
source "$repo/scripts/dev/slurm_local_cluster.sh"
trap slurm_local_stop EXIT
slurm_local_start "$work/cluster"

# Submits MANIFEST as arrays into WORK/NAME/slurm_out, waits at most WAIT_S seconds, checks every
# array element and the collect job left a log and every task finished, runs the manifest locally
# into WORK/NAME/local_out and compares the summaries.
slurm_against_local() {
  local name=$1 manifest=$2 wait_s=$3
  local dir="$work/$name" chunk=2
  mkdir -p "$dir"
  local total elements=0 count
  total=$("$exe" batch "$manifest" --out "$dir/slurm_out" --list | tail -n +2 | wc -l)
  for count in $("$exe" batch "$manifest" --out "$dir/slurm_out" --list | tail -n +2 |
    cut -f4 | uniq -c | awk '{print $1}'); do
    elements=$((elements + (count + chunk - 1) / chunk))
  done
  "$exe" batch "$manifest" --out "$dir/slurm_out" --slurm --submit --chunk "$chunk" --cpus 1 |
    tee "$dir/submit.txt"
  local array_ids collect_id
  array_ids=$(sed -n 's/.*submitted array jobs\{0,1\} \([0-9, ]*\) and collect job.*/\1/p' "$dir/submit.txt" | tr -d ' ')
  collect_id=$(sed -n 's/.*and collect job \([0-9]*\).*/\1/p' "$dir/submit.txt")
  [[ -n $array_ids && -n $collect_id ]] || { echo "FAILED: no job ids from --submit" >&2; return 1; }

  local start=$SECONDS
  while ((SECONDS - start < wait_s)); do
    [[ -z $(squeue -h -j "$array_ids,$collect_id" 2>/dev/null) ]] && break
    sleep 0.5
  done
  if [[ -n $(squeue -h -j "$array_ids,$collect_id" 2>/dev/null) ]]; then
    squeue >&2
    echo "FAILED: $name: the Slurm jobs did not finish in $wait_s s" >&2
    return 1
  fi
  local slurm_dir="$dir/slurm_out/slurm" logs
  logs=$(find "$slurm_dir" -name 'slurm-batch-*.out' -size +0 | wc -l)
  if ((logs != elements)) || [[ ! -s $slurm_dir/slurm-collect-$collect_id.out ]]; then
    echo "FAILED: $name: $logs of $elements array elements and" \
      "$( [[ -s $slurm_dir/slurm-collect-$collect_id.out ]] && echo the || echo no) collect job left a log" >&2
    ls -la "$slurm_dir" >&2
    tail -n 30 "$work"/cluster/log/* >&2
    return 1
  fi
  cat "$slurm_dir"/slurm-*.out
  if ! grep -q "batch: $total tasks, $total ok, 0 failed, 0 missing" "$slurm_dir/slurm-collect-$collect_id.out"; then
    echo "FAILED: $name: the collect job did not find $total finished tasks" >&2
    return 1
  fi

  "$exe" batch "$manifest" --out "$dir/local_out" --jobs 2 >"$dir/local.txt" 2>&1 ||
    { cat "$dir/local.txt" >&2; echo "FAILED: $name: the local run failed" >&2; return 1; }
  local f compared=0
  for f in summary.md summary.csv summary_monte_carlo.md summary_monte_carlo.csv; do
    [[ -e $dir/local_out/$f ]] || continue
    compared=$((compared + 1))
    if ! cmp "$dir/local_out/$f" "$dir/slurm_out/$f"; then
      diff "$dir/local_out/$f" "$dir/slurm_out/$f" >&2 || true
      echo "FAILED: $name: $f of the Slurm run differs from the local run" >&2
      return 1
    fi
  done
  ((compared >= 2)) || { echo "FAILED: $name: the local run wrote no summary" >&2; return 1; }
  echo "slurm_batch_test: $name: $total tasks ran as Slurm arrays $array_ids ($elements elements)," \
    "collect job $collect_id; $compared summaries identical to the local run"
}

cat >"$work/manifest.yaml" <<YAML
out: out_unused
config: $repo/configs/batch/tiny_tasks_run.yaml
cases: [$repo/data/sample_tactical, $repo/data/sample_mems]
estimators: [ekf]
seeds: [1, 2]
outage_schedules:
  - {length_s: 60, period_s: 110, start_s: 60}
YAML
slurm_against_local earlier_layout "$work/manifest.yaml" 90
slurm_against_local workbench "$repo/configs/batch/workbench.yaml" 400
