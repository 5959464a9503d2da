#!/usr/bin/env bash
# The worked estimator study of docs/batch.md (configs/batch/study_window.yaml): fgo-window with
# fgo.window_nodes 5, 10, 20 beside ekf, rts and fgo on the bundled samples and the real drives.
# Runs the batch (a drive where an estimator fails leaves a failed task; the study keeps the drives
# where every estimator ran), then batch_window_study.py writes the table from results.sqlite.
#   scripts/experiments/batch_window_study.sh [OUT_DIR]
#   env: GRAFTNAV (default build/graftnav); DOCS=1 rewrites the study's table in docs/batch.md and
#   copies the run's plots to docs/img/batch/.
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/../.." && pwd)"
OUT="${1:-$ROOT/out/batch_window_study}"
GN="${GRAFTNAV:-$ROOT/build/graftnav}"
PY=/usr/bin/python3; [ -x "$PY" ] || PY=python3
if [ ! -x "$GN" ]; then echo "batch_window_study: $GN not built (bash scripts/setup.sh)" >&2; exit 2; fi
mkdir -p "$OUT"
start=$(date +%s)
if ! "$GN" batch "$ROOT/configs/batch/study_window.yaml" --out "$OUT" 2>"$OUT/batch.log"; then
  echo "batch_window_study: some tasks failed (report: $OUT/report.md); the table keeps the" \
    "drives where every estimator ran" >&2
fi
echo "batch_window_study: batch took $(($(date +%s) - start)) s"
args=("$OUT")
if [ "${DOCS:-0}" = 1 ]; then
  args+=(--docs "$ROOT/docs/batch.md")
  mkdir -p "$ROOT/docs/img/batch"
  for p in report_options.png report_estimators.png; do
    [ -f "$OUT/$p" ] && cp "$OUT/$p" "$ROOT/docs/img/batch/window_study_${p#report_}"
  done
fi
"$PY" "$ROOT/scripts/experiments/batch_window_study.py" "${args[@]}"
