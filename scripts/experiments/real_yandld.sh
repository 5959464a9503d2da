#!/usr/bin/env bash
# yandld_20220405_rtk end to end (docs/real-data.md): GNSS selection, in-motion alignment, EKF/RTS/FGO
# with 60-s outages every 180 s, errors at the withheld RTK-fixed epochs and vs reference.nav,
# GNSS time-tag latency scan and the effect of correcting it, `graftnav compare` table and plot.
# Usage: scripts/experiments/real_yandld.sh [OUT_DIR]   (env: GRAFTNAV=path/to/graftnav, GRAFTNAV_REAL_DATA=dir,
#        DOCS_IMG=dir to also copy the plots, e.g. docs/img/real)
set -euo pipefail
REAL_CASE_NAME=yandld_20220405_rtk DEFAULT_OUT=/tmp/graftnav_real/yandld
# shellcheck source=real_case_env.sh
source "$(dirname "$0")/real_case_env.sh"
CFG="$ROOT/configs/real/yandld.yaml"
PROF="$ROOT/configs/real/yandld_mems.yaml"
# 1. estimators, check points, latency scan and latency grid (tables in $OUT/real/summary.md)
"$GN" real "$CASE" --out "$OUT/real" --run-config "$CFG" --imu tested --profile "$PROF" --estimator ekf,rts,fgo \
  --latency-scan --latency-grid 0,0.2,0.4,0.6 --latency-types 4,5 2>&1 | tee "$OUT/real.log"
# 2. graftnav compare against reference.nav (three estimators: table; EKF and RTS: plot)
"$GN" compare "$CASE" --out "$OUT/compare" --run-config "$CFG" --profile "$PROF" --lenient --imu tested \
  --estimator ekf,rts,fgo 2>&1 | tee "$OUT/compare.log"
"$GN" compare "$CASE" --out "$OUT/compare_plot" --run-config "$CFG" --profile "$PROF" --lenient --imu tested \
  --estimator ekf,rts > "$OUT/compare_plot.log" 2>&1
"$PY" "$ROOT/scripts/runtime/plot_compare.py" "$OUT/compare_plot"
"$PY" "$ROOT/scripts/runtime/plot_real.py" latency "$OUT/real" "$OUT/yandld_latency.png"
if [ -n "${DOCS_IMG:-}" ]; then
  mkdir -p "$DOCS_IMG"
  cp "$OUT/yandld_latency.png" "$DOCS_IMG/"
  [ -f "$OUT/compare_plot/compare.png" ] && cp "$OUT/compare_plot/compare.png" "$DOCS_IMG/yandld_compare.png"
fi
echo "real_yandld: tables in $OUT/real/summary.md and $OUT/compare/compare.md"
