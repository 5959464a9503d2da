#!/usr/bin/env bash
# Random concealed-effect cases for stress-testing `graftnav diagnose` on combinations it was not
# tuned on (docs/mismatch.md, "Random combinations"). Writes N simulator configs: each draws one to
# three effects from the candidate list, magnitudes log-uniform over ranges that straddle the
# finder's detection limits, random signs, a random piece of a random track, 100 or 200 Hz, a MEMS
# or tactical tested IMU, road vibration or not. Cases 0 mod 7 carry no concealed effect (nulls).
#
# Usage: scripts/experiments/make_random_cases.sh N SEED OUT_DIR [TESTED_PROFILE]
# then:  scripts/experiments/run_concealed_suite.sh --config-dir OUT_DIR --jobs 2 RESULT_DIR build/graftnav
# TESTED_PROFILE (a file name under configs/imu/, e.g. consumer_mems.yaml) replaces the drawn
# tested IMU; every other draw of the seed stays the same, so the cases pair with the seed's own.
# WIDE=1 adds the simulator's kinds the default list leaves out (gyro vibration rectification on
# either regressor, gyro asymmetries on all axes and two-sided, two-sided accelerometer
# asymmetries, gyro non-linearity) and draws one to four effects; without it a seed writes
# exactly the cases it always wrote.
set -euo pipefail
[ $# -eq 3 ] || [ $# -eq 4 ] || { sed -n '2,15p' "$0"; exit 2; }
n="$1" seed="$2" out="$3" profile="${4:-}"
repo="$(cd "$(dirname "$0")/../.." && pwd)"
if [ -n "$profile" ] && [ ! -f "$repo/configs/imu/$profile" ]; then
  echo "make_random_cases.sh: no tested IMU profile $repo/configs/imu/$profile" >&2; exit 2
fi
tracks="$(cd "$repo/../shared/data/tracks" && pwd)"
mkdir -p "$out"
awk -v n="$n" -v seed="$seed" -v out="$out" -v repo="$repo" -v tracks="$tracks" -v profile="$profile" \
    -v wide="${WIDE:-0}" '
function u(a, b) { return a + (b - a) * rand() }
function lu(a, b) { return exp(u(log(a), log(b))) }          # log-uniform in [a, b]
function sg() { return rand() < 0.5 ? -1 : 1 }
function vec(k, a, b,   i, s) {                                # k signed log-uniform values
  s = ""
  for (i = 0; i < k; ++i) s = s (i ? ", " : "") sprintf("%.4g", sg() * lu(a, b))
  return "[" s "]"
}
function pick(list, k,   m, arr, i, j, t, s) {               # k distinct items of a list
  m = split(list, arr, " ")
  for (i = m; i > 1; --i) { j = int(rand() * i) + 1; t = arr[i]; arr[i] = arr[j]; arr[j] = t }
  s = ""
  for (i = 1; i <= k && i <= m; ++i) s = s " " arr[i]
  return s
}
BEGIN {
  srand(seed)
  effects = "time_offset lever_arm misalignment gsens gyro_temperature accel_temperature " \
            "gyro_asymmetry accel_asymmetry quantization accel_nonlinearity accel_vibration"
  if (wide) effects = effects " gyro_vibration gyro_asym_all accel_asym_two gyro_nonlinearity"
  for (c = 1; c <= n; ++c) {
    name = sprintf("random_%d_%02d", seed, c)
    f = out "/" name ".yaml"
    k = (c % 7 == 0) ? 0 : int(u(1, wide ? 5 : 4))
    chosen = k ? pick(effects, k) : ""
    long = rand() < 0.5
    track = long ? "wuhan_57min_rtk.pos" : "wuhan_27min_rtk.pos"
    dur = int(u(600, 1200))
    start = int(u(60, (long ? 3300 : 1560) - dur))
    tested = rand() < 0.7 ? "pos1100_mems.yaml" : "pos310_tactical.yaml"
    if (profile != "") tested = profile
    printf "# Random concealed-effect case (scripts/experiments/make_random_cases.sh %d %d): %s\n", n, seed, (k ? chosen : " none (null)") > f
    printf "name: %s\nseed: %d\ngnss_week: 2100\nimu_rate_hz: %d\nquadrature_nodes: 4\ntruth_rate_hz: 10\n", name, seed * 100 + c, (rand() < 0.5 ? 100 : 200) > f
    printf "trajectory:\n  track: %s/%s\n  start_offset_s: %d\n  duration_s: %d\n", tracks, track, start, dur > f
    printf "  position_cutoff_hz: 0.4\n  attitude_cutoff_hz: 0.3\n  roll_deg_per_g: 4.0\n  oscillation_scale: 1.0\n" > f
    if (rand() < 0.5 || index(chosen, "vibration"))
      printf "  vibration:\n    accel_rms_m_s2: %.3g\n    gyro_rms_deg_s: %.3g\n    band_hz: [8, 40]\n    components: 12\n    seed: %d\n    half_amplitude_speed_m_s: 5\n", u(0.3, 0.9), u(0.5, 1.5), c > f
    printf "reference_imu:\n  profile: %s/configs/imu/pos830_navigation.yaml\n  turn_on_errors: true\n", repo > f
    printf "tested_imu:\n  profile: %s/configs/imu/%s\n  turn_on_errors: true\n", repo, tested > f
    printf "  gyro_bias_deg_h: %s\n  accel_bias_mg: %s\n", vec(3, 2, 15), vec(3, 0.3, 2) > f
    printf "  gyro_scale_ppm: %s\n  accel_scale_ppm: %s\n", vec(3, 200, 1500), vec(3, 200, 1500) > f
    printf "  gyro_nonorthogonality_urad: %s\n  accel_nonorthogonality_urad: %s\n", vec(6, 50, 500), vec(6, 50, 500) > f
    temp = 0
    if (index(chosen, "time_offset")) printf "  time_offset_s: %.4g\n", sg() * lu(0.001, 0.03) > f
    if (index(chosen, "lever_arm")) printf "  lever_arm_m: %s\n", vec(3, 0.01, 0.2) > f
    if (index(chosen, "misalignment")) printf "  mounting_misalignment_deg: %s\n", vec(3, 0.03, 0.5) > f
    if (index(chosen, "gsens")) printf "  g_sensitivity_deg_h_per_g: %s\n", vec(9, 10, 120) > f
    if (index(chosen, "gyro_temperature")) { printf "  gyro_bias_per_degC_deg_h: %s\n", vec(3, 0.5, 5) > f; temp = 1 }
    if (index(chosen, "accel_temperature")) { printf "  accel_bias_per_degC_mg: %s\n", vec(3, 0.03, 0.3) > f; temp = 1 }
    if (index(chosen, "gyro_asymmetry") && !index(chosen, "gyro_asym_all")) { a = lu(500, 4000); printf "  gyro_scale_asymmetry_pos_ppm: [0, 0, %.4g]\n  gyro_scale_asymmetry_neg_ppm: [0, 0, %.4g]\n", a, -a > f }
    if (index(chosen, "accel_asymmetry") && !index(chosen, "accel_asym_two")) { printf "  accel_scale_asymmetry_pos_ppm: %s\n  accel_scale_asymmetry_neg_ppm: [0, 0, 0]\n", vec(3, 1000, 8000) > f }
    if (index(chosen, "quantization")) {
      q = lu(1e-6, 8e-6); p = lu(1e-5, 8e-5)
      printf "  gyro_quantization_rad: [%.3g, %.3g, %.3g]\n  accel_quantization_m_s: [%.3g, %.3g, %.3g]\n", q, q, q, p, p, p > f
    }
    if (index(chosen, "accel_nonlinearity")) printf "  accel_scale_nonlinearity_per_m_s2: %s\n", vec(3, 5e-5, 2e-3) > f
    if (index(chosen, "gyro_vibration")) {
      if (rand() < 0.5) printf "  gyro_vibration_rectification:\n    coeff: %s\n    regressor: specific_force_hp_sq\n    window_s: 1\n", vec(3, 3e-5, 1e-3) > f
      else printf "  gyro_vibration_rectification:\n    coeff: %s\n    regressor: angular_rate_hp_sq\n    window_s: 1\n", vec(3, 3e-3, 1e-1) > f
    }
    if (index(chosen, "gyro_asym_all")) printf "  gyro_scale_asymmetry_pos_ppm: %s\n  gyro_scale_asymmetry_neg_ppm: %s\n", vec(3, 300, 4000), vec(3, 300, 4000) > f
    if (index(chosen, "accel_asym_two")) printf "  accel_scale_asymmetry_pos_ppm: %s\n  accel_scale_asymmetry_neg_ppm: %s\n", vec(3, 1000, 8000), vec(3, 1000, 8000) > f
    if (index(chosen, "gyro_nonlinearity")) printf "  gyro_scale_nonlinearity_per_rad_s: %s\n", vec(3, 1e-3, 5e-2) > f
    if (index(chosen, "accel_vibration")) printf "  accel_vibration_rectification:\n    coeff: %s\n    regressor: specific_force_hp_sq\n    window_s: 1\n", vec(3, 5e-4, 2e-2) > f
    if (temp) {
      printf "  temperature_ref_degC: 25\ntemperature:\n" > f
      t0 = u(5, 25)
      printf "  start_degC: %.3g\n  end_degC: %.3g\n  time_constant_s: %d\n  lab_degC: 25\n", t0, t0 + u(8, 25), int(u(300, 900)) > f
    }
    printf "gnss:\n  rate_hz: 1\n  noise_std_neu_m: [0.02, 0.02, 0.04]\n  lever_arm_m: [0.1, -0.2, -1.2]\n" > f
    printf "lab:\n  latitude_deg: 30.53\n  longitude_deg: 114.35\n  height_m: 25\n  start_time_s: 100000\n" > f
    printf "  static_duration_s: 600\n  static_attitude_deg: [0, 0, 0]\n  six_position_duration_s: 30\n" > f
    printf "  rate_table_deg_s: [30, 90]\n  rate_table_turns: 1\n  tilt_duration_s: 10\n  tilts: {tilt_mixed: [-10, 25, 135]}\n" > f
    close(f)
    print f
  }
}'
