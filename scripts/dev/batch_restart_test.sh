#!/usr/bin/env bash
# Kill-and-restart proof of `graftnav batch` (run by CTest as batch_restart_100 and, on the
# workbench manifest with a group of every command, batch_restart_workbench):
#   1. runs MANIFEST uninterrupted into WORK/reference;
#   2. runs it into WORK/resumed and kills it (SIGKILL, by pid) once half of the tasks finished;
#   3. restarts it and checks that exactly the unfinished tasks ran (the restart's own count),
#      that no finished task's record changed (each task.sqlite is compared by checksum; a rerun
#      would rewrite it with a new run time), and that the summaries equal the reference byte
#      for byte.
#
#   bash scripts/dev/batch_restart_test.sh build/graftnav /tmp/restart [configs/batch/restart_100.yaml] [JOBS]
set -euo pipefail
if (($# < 2)); then
  echo "usage: $0 GRAFTNAV_BINARY WORK_DIR [MANIFEST] [JOBS]" >&2
  exit 2
fi
repo=$(cd "$(dirname "$0")/../.." && pwd)
exe=$(realpath "$1")
work=$2
manifest=${3:-$repo/configs/batch/restart_100.yaml}
jobs=${4:-2}
rm -rf "$work"
mkdir -p "$work"

total=$("$exe" batch "$manifest" --out "$work/reference" --list | tail -n +2 | wc -l)
half=$((total / 2))
echo "batch_restart_test: $total tasks, killing the second run after $half finished"

t0=$(date +%s.%N)
"$exe" batch "$manifest" --out "$work/reference" --jobs "$jobs" 2>"$work/reference.log"
t1=$(date +%s.%N)

count_done() { find "$work/resumed/tasks" -name task.sqlite 2>/dev/null | wc -l; }
"$exe" batch "$manifest" --out "$work/resumed" --jobs "$jobs" >"$work/first.out" 2>"$work/first.log" &
pid=$!
while (($(count_done) < half)); do
  if ! kill -0 "$pid" 2>/dev/null; then
    echo "FAILED: the first run ended before half of the tasks finished" >&2
    exit 1
  fi
  sleep 0.05
done
kill -KILL "$pid"
wait "$pid" 2>/dev/null || true
done_at_kill=$(count_done)
(cd "$work/resumed/tasks" && find . -name task.sqlite -print0 | sort -z | xargs -0 sha256sum) >"$work/finished_at_kill.sha256"
if [[ -e $work/resumed/summary.csv ]]; then
  echo "FAILED: the killed run got to its summary; nothing was interrupted" >&2
  exit 1
fi

t2=$(date +%s.%N)
"$exe" batch "$manifest" --out "$work/resumed" --jobs "$jobs" >"$work/restart.out" 2>"$work/restart.log"
t3=$(date +%s.%N)
cat "$work/restart.out"

status=0
expected="batch: $((total - done_at_kill)) ran, $done_at_kill skipped (finished before), 0 failed"
if ! grep -qxF "$expected" "$work/restart.out"; then
  echo "FAILED: expected '$expected'" >&2
  status=1
fi
if ! (cd "$work/resumed/tasks" && sha256sum --quiet -c "$work/finished_at_kill.sha256"); then
  echo "FAILED: a task finished before the kill was run again (its record changed)" >&2
  status=1
fi
for f in summary.md summary.csv summary_monte_carlo.md summary_monte_carlo.csv; do
  [[ -e $work/reference/$f || -e $work/resumed/$f ]] || continue  # no seeds: no Monte-Carlo summary
  if ! cmp "$work/reference/$f" "$work/resumed/$f"; then
    echo "FAILED: $f after the restart differs from the uninterrupted run" >&2
    status=1
  fi
done
((status == 0)) || exit 1
printf 'batch_restart_test: %d tasks; uninterrupted %.1f s; killed with %d finished; restart ran %d, skipped %d in %.1f s; summaries identical\n' \
  "$total" "$(awk "BEGIN {print $t1 - $t0}")" "$done_at_kill" "$((total - done_at_kill))" "$done_at_kill" "$(awk "BEGIN {print $t3 - $t2}")"
