#!/usr/bin/env bash
# The vehicle-aiding study of docs/aiding.md: simulates the 25-minute land drive
# (configs/sim/land_drive_25min.yaml: 5-18 m/s, the bundled MEMS sample's IMU, an odometer 3000
# ppm fast with 0.05 m/s noise), navigates its tested IMU with ekf, rts, fgo and fgo-window
# through 60 s outages every 180 s without aiding (configs/aiding/land_drive.yaml) and with the
# odometer and NHC (land_drive_aided.yaml), and writes the table (outage horizontal RMS of
# errors.json, the estimated odometer scale against the injected one).
#
# Usage: scripts/experiments/aiding_table.sh [--inject DOC] [--table FILE] OUT_DIR [GRAFTNAV]
#   --inject DOC   replace the aiding_table block of DOC (docs/aiding.md) with the summary
#   --table FILE   write the full table (docs/results/aiding-land-drive.md)
set -euo pipefail
repo="$(cd "$(dirname "$0")/../.." && pwd)"
inject=""; table=""; pos=()
while [ $# -gt 0 ]; do
  case "$1" in
    --inject) inject="$2"; shift 2 ;;
    --table) table="$2"; shift 2 ;;
    -h|--help) sed -n '2,12p' "$0"; exit 0 ;;
    --*) echo "aiding_table: unknown option $1" >&2; exit 2 ;;
    *) pos+=("$1"); shift ;;
  esac
done
[ ${#pos[@]} -ge 1 ] || { echo "usage: scripts/experiments/aiding_table.sh [options] OUT_DIR [GRAFTNAV]" >&2; exit 2; }
out="$(mkdir -p "${pos[0]}" && cd "${pos[0]}" && pwd)"
bin="$(realpath "${pos[1]:-$repo/build/graftnav}")"
case_dir="$out/case"
mkdir -p "$out/runs"
[ -f "$case_dir/field/odometer.txt" ] ||
  "$bin" simulate --sim-config "$repo/configs/sim/land_drive_25min.yaml" --out "$case_dir" > "$out/simulate.log" 2>&1
for est in ekf rts fgo fgo-window; do
  for mode in free aided; do
    cfg="$repo/configs/aiding/land_drive.yaml"
    [ "$mode" = aided ] && cfg="$repo/configs/aiding/land_drive_aided.yaml"
    run="$out/runs/${est}_$mode"
    [ -f "$run/errors.json" ] && continue
    /usr/bin/time -f "%e s %M KB" -o "$run.time" \
      "$bin" navigate "$case_dir" --out "$run" --imu tested --estimator "$est" --run-config "$cfg" \
      --no-plots > "$run.log" 2>&1 || { echo "aiding_table: $est $mode failed (see $run.log)" >&2; exit 1; }
    echo "aiding_table: $est $mode done ($(cat "$run.time"))"
  done
done
/usr/bin/python3 "$repo/scripts/experiments/aiding_table.py" "$out" \
  --command "scripts/experiments/aiding_table.sh${inject:+ --inject $inject}${table:+ --table $table} OUT" ${table:+--out "$table"} ${inject:+--inject "$inject"}
