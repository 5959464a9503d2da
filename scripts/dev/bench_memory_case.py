#!/usr/bin/env python3
"""The motion-script simulation config of a bench_memory.sh case: MINUTES of driving (static start,
cruise legs with turns, stop), 200 Hz IMUs and truth, the POS830 reference and POS1100 tested
profiles, a 1-h lab static record.

Usage: bench_memory_case.py MINUTES CONFIGS_IMU_DIR > sim.yaml
"""
import sys
minutes, imu = int(sys.argv[1]), sys.argv[2]
dur = 60 * minutes
segs = ["{type: static, duration_s: 60}", "{type: accelerate, to_speed_m_s: 10, duration_s: 10}"]
t = 70
while t + 110 <= dur - 30:
    segs += ["{type: cruise, duration_s: 100}", "{type: turn, rate_deg_s: 9, duration_s: 10}"]
    t += 110
segs += ["{type: cruise, duration_s: %d}" % max(1, dur - 30 - t), "{type: stop, duration_s: 10}",
         "{type: static, duration_s: 20}"]
print(f"""name: bench_{minutes}min
seed: 36
gnss_week: 2100
imu_rate_hz: 200
truth_rate_hz: 200
trajectory:
  script:
    start_time_s: 100000
    start_position: [30.5, 114.3, 20]
    initial_yaw_deg: 30
    segments:""")
for s in segs:
    print("      - " + s)
print(f"""reference_imu:
  profile: {imu}/pos830_navigation.yaml
tested_imu:
  profile: {imu}/pos1100_mems.yaml
  gyro_bias_deg_h: [8, -6, 10]
  accel_bias_mg: [0.8, -0.6, 1.0]
  gyro_scale_ppm: [800, -600, 900]
  accel_scale_ppm: [-700, 900, 600]
gnss:
  rate_hz: 1
  noise_std_neu_m: [0.02, 0.02, 0.04]
  lever_arm_m: [0.1, -0.2, -1.2]
lab:
  static_duration_s: 3600
  six_position_duration_s: 30
  rate_table_deg_s: [30, 90]
  tilt_duration_s: 30
  tilts: {{tilt_mixed: [-10, 25, 135]}}""")
