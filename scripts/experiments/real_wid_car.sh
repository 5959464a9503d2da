#!/usr/bin/env bash
# wid_car_trial07 end to end (docs/real-data.md): MRU-P and Xsens DOT navigated with the same GNSS
# and 20-s outages, the DOT predicted from the MRU-P (real-data SG#1 from the DOT's standstill spans)
# with EKF and RTS, ERR/DIFF against SOL_REF, and `graftnav diagnose` on the pair.
# Usage: scripts/experiments/real_wid_car.sh [OUT_DIR]   (env: GRAFTNAV, GRAFTNAV_REAL_DATA, DOCS_IMG as in real_yandld.sh)
set -euo pipefail
REAL_CASE_NAME=wid_car_trial07 DEFAULT_OUT=/tmp/graftnav_real/wid_car
# shellcheck source=real_case_env.sh
source "$(dirname "$0")/real_case_env.sh"
# The DOT at standstill vibrates with the engine (gyro 0.014 rad/s, accel 0.57 m/s^2 std over 1 s):
# detector thresholds just above that; spans with a median GNSS speed > 0.3 m/s are dropped.
for EST in rts ekf; do
  "$GN" real-sg "$CASE" --out "$OUT/sg_$EST" --estimator "$EST" --run-config "$ROOT/configs/real/wid_car.yaml" \
    --ref-profile "$ROOT/configs/real/wid_mrup.yaml" --tested-profile "$ROOT/configs/real/wid_dot.yaml" \
    --static-gyro-threshold 0.02 --static-accel-threshold 0.65 2>&1 | tee "$OUT/sg_$EST.log"
done
"$GN" diagnose "$CASE" --out "$OUT/diagnose" --no-plots 2>&1 | tee "$OUT/diagnose.log"
"$PY" "$ROOT/scripts/runtime/plot_real.py" sg "$OUT/sg_rts" "$OUT/wid_sg_rts.png"
"$PY" "$ROOT/scripts/runtime/plot_real.py" sg "$OUT/sg_ekf" "$OUT/wid_sg_ekf.png"
if [ -n "${DOCS_IMG:-}" ]; then
  mkdir -p "$DOCS_IMG"
  cp "$OUT/wid_sg_rts.png" "$OUT/wid_sg_ekf.png" "$DOCS_IMG/"
fi
echo "real_wid_car: tables in $OUT/sg_rts/summary.md, $OUT/sg_ekf/summary.md, $OUT/diagnose/diagnosis.md"
