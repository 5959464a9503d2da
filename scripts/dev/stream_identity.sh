#!/usr/bin/env bash
# Runs two graftnav binaries on the same navigate and compare inputs and compares every file they
# write with `cmp` (run_info.json with its timing lines left out): the bundled samples with a
# static alignment, a time range alone, and both (outages at the range's edges), an in-motion
# alignment with and without a range, and the real
# recordings with their run configs. Used to show that the streamed inputs of a data alignment
# or a time range write what the in-memory ones write.
#
# Usage: scripts/dev/stream_identity.sh BINARY_A BINARY_B OUT_DIR [--estimators LIST]
set -euo pipefail
repo="$(cd "$(dirname "$0")/../.." && pwd)"
a="$(realpath "$1")"; b="$(realpath "$2")"; out="$3"; shift 3
estimators="ekf fgo-window rts fgo"
while [ $# -gt 0 ]; do
  case "$1" in
    --estimators) estimators="$2"; shift 2 ;;
    *) echo "unknown option $1" >&2; exit 2 ;;
  esac
done
real="${GRAFTNAV_REAL_DATA:-$repo/../shared/data/real}"
mkdir -p "$out"
base="$repo/configs/navigate.yaml"
# A copy of configs/navigate.yaml with `ekf.alignment` and the lines after `evaluation:` replaced.
config() {  # name, alignment, static_alignment_s, extra top-level YAML
  sed -e "s/^  alignment: given.*/  alignment: $2/" -e "s/^  static_alignment_s: .*/  static_alignment_s: $3/" \
    "$base" > "$out/$1.yaml"
  printf "%b" "$4" >> "$out/$1.yaml"
}
config static static 15 ""
config range given 60 "time_range:\n  start_s: 456430\n  end_s: 457150\n"
config static_range static 30 \
  "time_range:\n  start_s: 456430\n  end_s: 457150\n"
sed -i -e "s/^  # windows: .*/  windows: [[456470, 456530], [457090, 457150]]/" "$out/static_range.yaml"
config motion motion 60 ""
config motion_range motion 60 "time_range:\n  start_s: 456430\n  end_s: 457150\n"

failures=0
# A file with what differs between two runs of the same inputs taken out: the binary's and the
# output folder's paths, the git commit and the run times (run_info.json, compare's run column).
normalized() {  # file, binary
  local name; name="$(basename "$1")"
  sed -e "s#$2#BIN#g" -e "s#$out/[AB]/#OUT/#g" -e '/"git_commit"/d' -e '/"run_time_s"/d' \
    -e '/"run_s"/d' "$1" |
    case "$name" in
      compare.csv) cut -d, -f1-8,10- ;;
      compare.md) sed -E 's/\| [0-9.]+ \| ([0-9]+) \|$/| - | \1 |/' ;;
      *) cat ;;
    esac
}
compare_dirs() {  # name
  local da="$out/A/$1" db="$out/B/$1" f
  for f in $(cd "$da" && find . -type f ! -name '*.png' | sort); do
    case "$(basename "$f")" in
      run_info.json | compare.csv | compare.md | compare.json)
        cmp -s <(normalized "$da/$f" "$a") <(normalized "$db/$f" "$b") ;;
      *) cmp -s "$da/$f" "$db/$f" ;;
    esac || { echo "DIFF $1/$f"; failures=$((failures + 1)); }
  done
  if [ "$(cd "$da" && find . -type f | sort)" != "$(cd "$db" && find . -type f | sort)" ]; then
    echo "DIFF $1: other files"; failures=$((failures + 1))
  fi
}
run_both() {  # name, then the arguments after the binary with OUT standing for the output folder
  local name="$1"; shift
  for side in A B; do
    local bin="$a"; [ "$side" = B ] && bin="$b"
    local args=("${@//OUT/$out/$side/$name}")
    local rc=0
    "$bin" "${args[@]}" > "$out/$side/$name.log" 2>&1 || rc=$?
    echo "$rc" > "$out/$side/$name.rc"
  done
  if ! cmp -s "$out/A/$name.rc" "$out/B/$name.rc"; then
    echo "DIFF $name: exit codes $(cat "$out/A/$name.rc") and $(cat "$out/B/$name.rc")"
    failures=$((failures + 1))
  elif [ -d "$out/A/$name" ]; then
    compare_dirs "$name"
  fi
  echo "$name: exit $(cat "$out/A/$name.rc")"
}
mkdir -p "$out/A" "$out/B"
for grade in mems tactical; do
  for cfg in static range static_range motion motion_range; do
    for e in $estimators; do
      run_both "navigate_${grade}_${cfg}_$e" navigate "$repo/data/sample_$grade" --out OUT \
        --imu tested --estimator "$e" --run-config "$out/$cfg.yaml" --no-plots
    done
    run_both "compare_${grade}_${cfg}" compare "$repo/data/sample_$grade" --out OUT --imu tested \
      --estimator ekf,rts --run-config "$out/$cfg.yaml" --no-plots
  done
done
# The command line's bounds over the run config's.
run_both "navigate_mems_cli_range_ekf" navigate "$repo/data/sample_mems" --out OUT --imu tested \
  --estimator ekf --run-config "$out/static.yaml" --start 456340.5 --end 457000 --no-plots
wid=(--lenient --run-config "$repo/configs/real/wid_car.yaml" --no-plots)
yandld=(--lenient --imu tested --profile "$repo/configs/real/yandld_mems.yaml"
  --run-config "$repo/configs/real/yandld.yaml" --no-plots)
for e in $estimators; do
  run_both "navigate_wid_car_ref_$e" navigate "$real/wid_car_trial07" --out OUT --estimator "$e" \
    --imu ref --profile "$repo/configs/real/wid_mrup.yaml" "${wid[@]}"
  run_both "navigate_wid_car_tested_$e" navigate "$real/wid_car_trial07" --out OUT --estimator "$e" \
    --imu tested --profile "$repo/configs/real/wid_dot.yaml" "${wid[@]}"
  run_both "navigate_yandld_$e" navigate "$real/yandld_20220405_rtk" --out OUT --estimator "$e" \
    "${yandld[@]}"
done
run_both "navigate_wid_car_ref_range_ekf" navigate "$real/wid_car_trial07" --out OUT --estimator ekf \
  --imu ref --profile "$repo/configs/real/wid_mrup.yaml" --start 100002 --end 100140 "${wid[@]}"
run_both "compare_wid_car" compare "$real/wid_car_trial07" --out OUT --estimator ekf,rts \
  --imu ref --profile "$repo/configs/real/wid_mrup.yaml" "${wid[@]}"
echo "$failures difference(s)"
[ "$failures" = 0 ]
