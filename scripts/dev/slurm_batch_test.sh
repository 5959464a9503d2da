#!/usr/bin/env bash
# The batch on a real Slurm: starts a one-node cluster on localhost (scripts/dev/slurm_local_cluster.sh),
# submits a small manifest as an array (`graftnav batch --slurm --submit`, 4 tasks in 2 array
# elements), waits for the array and the collect job, runs the same manifest locally and compares
# the summaries byte for byte. Stops the daemons it started, by pid. Run by CTest
# (slurm_batch_localhost); needs root, and FAILS when munge or slurm-wlm is missing.
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

cat >"$work/manifest.yaml" <<YAML
out: out_unused
config: $repo/configs/batch/tiny_tasks_run.yaml
cases: [$repo/data/sample_tactical, $repo/data/sample_mems]
estimators: [ekf]
seeds: [1, 2]
outage_schedules:
  - {length_s: 60, period_s: 110, start_s: 60}
YAML

"$exe" batch "$work/manifest.yaml" --out "$work/slurm_out" --slurm --submit --chunk 2 --cpus 1 | tee "$work/submit.txt"
array_id=$(sed -n 's/.*submitted array job \([0-9]*\) and collect job \([0-9]*\).*/\1/p' "$work/submit.txt")
collect_id=$(sed -n 's/.*submitted array job \([0-9]*\) and collect job \([0-9]*\).*/\2/p' "$work/submit.txt")
[[ -n $array_id && -n $collect_id ]] || { echo "FAILED: no job ids from --submit" >&2; exit 1; }

# Wait (at most 90 s) until neither job is queued or running.
for _ in $(seq 450); do
  [[ -z $(squeue -h -j "$array_id,$collect_id" 2>/dev/null) ]] && break
  sleep 0.2
done
if [[ -n $(squeue -h -j "$array_id,$collect_id" 2>/dev/null) ]]; then
  squeue >&2
  echo "FAILED: the Slurm jobs did not finish in 90 s" >&2
  exit 1
fi

slurm_dir="$work/slurm_out/slurm"
status=0
for element in 0 1; do
  log="$slurm_dir/slurm-batch-${array_id}_${element}.out"
  [[ -s $log ]] || { echo "FAILED: array element $element left no log ($log)" >&2; status=1; }
done
[[ -s $slurm_dir/slurm-collect-$collect_id.out ]] || { echo "FAILED: the collect job left no log" >&2; status=1; }
if ((status)); then
  ls -la "$slurm_dir" >&2
  tail -n 30 "$work"/cluster/log/* >&2
  exit 1
fi
cat "$slurm_dir"/slurm-*.out

"$exe" batch "$work/manifest.yaml" --out "$work/local_out" --jobs 2
for f in summary.md summary.csv summary_monte_carlo.md summary_monte_carlo.csv; do
  if ! cmp "$work/local_out/$f" "$work/slurm_out/$f"; then
    diff "$work/local_out/$f" "$work/slurm_out/$f" >&2 || true
    echo "FAILED: $f of the Slurm run differs from the local run" >&2
    exit 1
  fi
done
echo "slurm_batch_test: 4 tasks ran as Slurm array $array_id (2 elements), collect job $collect_id;" \
  "summaries identical to the local run"
