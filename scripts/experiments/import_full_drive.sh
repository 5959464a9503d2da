#!/usr/bin/env bash
# The KF-GINS import on a full drive: a KF-GINS set-up (IMU file, GNSS file with the outage
# stretches deleted, kf-gins.yaml with the case's tested-IMU noise in KF-GINS units) made from a
# simulated case, then `graftnav import kf-gins` + `graftnav navigate`, against the same EKF set
# up by hand on the original case (explicit outage windows, gate off). Writes OUT/table.md.
# Usage: scripts/experiments/import_full_drive.sh OUT [CASE] [path/to/graftnav]
#   CASE default: OUT/case simulated from configs/sim/mems_57min.yaml (57 min, 200 Hz).
set -euo pipefail
OUT=$1
ROOT="$(cd "$(dirname "$0")/../.." && pwd)"
here="$(cd "$(dirname "$0")" && pwd)"
CASE=${2:-$OUT/case}
GN=${3:-$ROOT/build/graftnav}
mkdir -p "$OUT/kf"
[ -f "$CASE/case.yaml" ] || "$GN" simulate --sim-config "$ROOT/configs/sim/mems_57min.yaml" --out "$CASE" > "$OUT/simulate.log"

key() { sed -n "/^$1:/,/^[a-z]/p" "$CASE/case.yaml" | sed -n "s/^ *$2: *//p" | head -1 | tr -d '[]'; }
T0=$(key initial_state time)
T_END=$(tail -1 "$CASE/field/gnss.pos" | awk '{print $1}')
# Outages of the peers' usual schedule: 60 s every 180 s from 300 s after the start.
WINDOWS=$(awk -v t0="$T0" -v te="$T_END" 'BEGIN { for (s = t0 + 300; s + 60 <= te - 10; s += 180) printf "%.0f %.0f\n", s, s + 60 }')
awk -v w="$WINDOWS" 'BEGIN { n = split(w, a, /[ \n]/) } { keep = 1; for (i = 1; i < n; i += 2) if ($1 > a[i] && $1 < a[i+1]) keep = 0; if (keep) print }' \
  "$CASE/field/gnss.pos" > "$OUT/kf/gnss.txt"
ln -sf "$(cd "$CASE" && pwd)/field/tested_imu.txt" "$OUT/kf/imu.txt"
ln -sf "$(cd "$CASE" && pwd)/field/truth.nav" "$OUT/kf/truth.nav"
tested() { key tested_imu "$1"; }
RATE=$(sed -n 's/^tested_imu_rate_hz: *//p' "$CASE/case.yaml")
[ -n "$RATE" ] || RATE=$(sed -n 's/^imu_rate_hz: *//p' "$CASE/case.yaml")
MGAL=$(awk -v mg="$(tested accel_bias_instability_mg)" 'BEGIN { printf "%.6g", mg * 980.665 }')
CORR_H=$(awk -v s="$(tested gyro_bias_correlation_time_s)" 'BEGIN { printf "%.6g", s / 3600 }')
cat > "$OUT/kf/kf-gins.yaml" <<YAML
imupath: "imu.txt"
gnsspath: "gnss.txt"
outputpath: "./out"
imudatalen: 7
imudatarate: $RATE
starttime: $T0
endtime: -1
initpos: [$(key initial_state position)]
initvel: [$(key initial_state velocity_ned)]
initatt: [$(key initial_state attitude_deg)]
initposstd: [0.5, 0.5, 0.5]
initvelstd: [0.1, 0.1, 0.1]
initattstd: [0.1, 0.1, 0.5]
imunoise:
  arw: $(tested arw_deg_rt_h)
  vrw: $(tested vrw_m_s_rt_h)
  gbstd: $(tested gyro_bias_instability_deg_h)
  abstd: $MGAL
  gsstd: $(tested gyro_scale_ppm)
  asstd: $(tested accel_scale_ppm)
  corrtime: $CORR_H
antlever: [$(sed -n 's/^lever_arm_m: *//p' "$CASE/case.yaml" | tr -d '[]')]
YAML
{
  echo "outages:"
  echo "  windows:"
  echo "$WINDOWS" | awk '{ printf "    - [%.3f, %.3f]\n", $1 + 0.001, $2 - 0.001 }'
  echo "ekf: {gate_probability: 0, init_pos_std_m: 0.5, init_vel_std_m_s: 0.1, init_roll_pitch_std_deg: 0.1, init_heading_std_deg: 0.5}"
} > "$OUT/hand.yaml"

"$GN" import kf-gins "$OUT/kf/kf-gins.yaml" --out "$OUT/imported_case" --reference "$OUT/kf/truth.nav" > "$OUT/import.log"
"$GN" navigate "$OUT/imported_case" --out "$OUT/imported" --no-plots > "$OUT/navigate_imported.log" 2>&1
"$GN" navigate "$CASE" --imu tested --run-config "$OUT/hand.yaml" --out "$OUT/hand" --no-plots > "$OUT/navigate_hand.log" 2>&1

python3 "$here/import_full_drive_table.py" "$OUT"
