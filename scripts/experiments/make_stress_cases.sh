#!/usr/bin/env bash
# Stress cases for `graftnav diagnose` beyond what the random generator draws (docs/mismatch.md,
# stress cases): one simulator case (random_33_13 of `make_random_cases.sh 28 33`: the
# 57-min Wuhan track, 200 Hz, road vibration, a POS1100-like tested IMU), its concealed effect
# replaced by
#   - single effects the default random list never draws: gyro vibration rectification on the
#     angular-rate and on the specific-force regressor, gyro non-linearity (the lab's rate table
#     measures it: expected "in SG#2 from the lab"), gyro asymmetries on all axes two-sided,
#     accelerometer asymmetries two-sided;
#   - large geometry: an 80-ms time offset, a 1-m lever arm, a 3.9-deg mounting rotation;
#   - six effects at once (time offset, lever arm, misalignment, g-sensitivity, gyro asymmetry,
#     accel vibration rectification) with POS1100-like, tactical and consumer tested IMUs, and
#     four at once with a 25-degC warm-up.
#
# Usage: scripts/experiments/make_stress_cases.sh OUT_DIR
# then:  scripts/experiments/run_concealed_suite.sh --config-dir OUT_DIR --jobs 2 RESULT_DIR build/graftnav
set -euo pipefail
[ $# -eq 1 ] || { sed -n '2,16p' "$0"; exit 2; }
out="$1"
repo="$(cd "$(dirname "$0")/../.." && pwd)"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
"$repo/scripts/experiments/make_random_cases.sh" 28 33 "$tmp" > /dev/null
base="$tmp/random_33_13.yaml"
grep -q "^  accel_vibration_rectification:" "$base" ||
  { echo "make_stress_cases.sh: $base no longer holds the expected base case" >&2; exit 1; }
mkdir -p "$out"

# case NAME SEED PROFILE TEXT: the base with name, noise seed and tested profile replaced and its
# accelerometer vibration rectification (4 lines) replaced by TEXT (printf escapes).
case_() {
  local name="$1" seed="$2" prof="$3" extra="$4"
  awk -v name="$name" -v seed="$seed" -v prof="$prof" -v extra="$extra" '
    /^# Random/ { print "# Stress case (scripts/experiments/make_stress_cases.sh), base random_33_13"; next }
    /^name:/ { print "name: " name; next }
    /^seed:/ { print "seed: " seed; next }
    /^  profile: .*pos1100_mems.yaml/ { sub("pos1100_mems.yaml", prof); print; next }
    /^  accel_vibration_rectification:/ { skip = 3; printf "%s", extra; next }
    skip > 0 { skip--; next }
    { print }' "$base" > "$out/$name.yaml"
  echo "$out/$name.yaml"
}

mems=pos1100_mems.yaml
case_ stress_gyro_vr_rate 3313 $mems "  gyro_vibration_rectification:\n    coeff: [0.03, -0.03, 0.025]\n    regressor: angular_rate_hp_sq\n    window_s: 1\n"
case_ stress_gyro_vr_force 3313 $mems "  gyro_vibration_rectification:\n    coeff: [0.0004, -0.0005, 0.0004]\n    regressor: specific_force_hp_sq\n    window_s: 1\n"
case_ stress_gyro_nonlinearity 3313 $mems "  gyro_scale_nonlinearity_per_rad_s: [0.03, 0.06, 0.004]\n"
case_ stress_gyro_asym_all 3313 $mems "  gyro_scale_asymmetry_pos_ppm: [2000, -1500, 800]\n  gyro_scale_asymmetry_neg_ppm: [-1000, 1500, -800]\n"
case_ stress_accel_asym_two 3313 $mems "  accel_scale_asymmetry_pos_ppm: [3000, -4000, 2000]\n  accel_scale_asymmetry_neg_ppm: [-2000, 3000, 0]\n"
case_ stress_time_offset_80ms 3313 $mems "  time_offset_s: 0.08\n"
case_ stress_lever_arm_1m 3313 $mems "  lever_arm_m: [0.8, -0.5, 0.3]\n"
case_ stress_misalignment_4deg 3313 $mems "  mounting_misalignment_deg: [1.5, -2.0, 3.0]\n"
six="  time_offset_s: -0.012\n  lever_arm_m: [0.15, -0.08, 0.05]\n  mounting_misalignment_deg: [0.3, -0.2, 0.4]\n  g_sensitivity_deg_h_per_g: [60, -40, 30, 50, 70, -30, -40, 20, 60]\n  gyro_scale_asymmetry_pos_ppm: [0, 0, 2500]\n  gyro_scale_asymmetry_neg_ppm: [0, 0, -2500]\n  accel_vibration_rectification:\n    coeff: [0.006, -0.005, 0.01]\n    regressor: specific_force_hp_sq\n    window_s: 1\n"
case_ stress_six_mems 9101 $mems "$six"
case_ stress_six_tactical 9102 pos310_tactical.yaml "$six"
case_ stress_six_consumer 9103 consumer_mems.yaml "$six"
case_ stress_four_warmup 9104 $mems "  time_offset_s: 0.005\n  gyro_bias_per_degC_deg_h: [2, -3, 1.5]\n  accel_scale_asymmetry_pos_ppm: [0, 5000, 0]\n  accel_scale_asymmetry_neg_ppm: [0, 0, 0]\n  gyro_quantization_rad: [4e-6, 4e-6, 4e-6]\n  temperature_ref_degC: 25\ntemperature:\n  start_degC: 10\n  end_degC: 35\n  time_constant_s: 400\n"
