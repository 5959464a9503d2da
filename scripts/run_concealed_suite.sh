#!/usr/bin/env bash
# Concealed-effects suite of the mismatch finder (issue 7 item 6, docs/mismatch.md): for every
# configs/sim/concealed/*.yaml, simulate the case, run `graftnav diagnose` with the EKF, and print a
# Markdown table: effect injected, effect found, parameter error, fit before/after (signal RMS and
# DIFF of the five outage statistics).
#
# Usage: scripts/run_concealed_suite.sh [OUT_DIR] [GRAFTNAV_BINARY]
#   OUT_DIR defaults to /tmp/graftnav_concealed; the binary to build/graftnav.
set -euo pipefail
repo="$(cd "$(dirname "$0")/.." && pwd)"
out="${1:-/tmp/graftnav_concealed}"
bin="${2:-$repo/build/graftnav}"
py="${GRAFTNAV_PYTHON:-/usr/bin/python3}"
[ -x "$py" ] || py=python3
mkdir -p "$out"
for cfg in "$repo"/configs/sim/concealed/*.yaml; do
  name="$(basename "$cfg" .yaml)"
  echo "== $name" >&2
  "$bin" simulate --config "$cfg" --out "$out/$name" > "$out/$name.simulate.log" 2>&1
  "$bin" diagnose "$out/$name" --out "$out/${name}_diag" --no-plots --estimator ekf \
    --outage-length 60 --outage-period 120 --outage-start 100 > "$out/$name.diagnose.log" 2>&1
done
"$py" - "$repo/configs/sim/concealed" "$out" <<'PYEOF'
import glob, json, math, os, sys
import yaml

cfg_dir, out = sys.argv[1], sys.argv[2]
DEG_H = math.pi / 180.0 / 3600.0   # deg/h -> rad/s
G0 = 9.80665
MG = 1e-3 * G0

def injected(cfg):
    t = cfg.get("tested_imu", {})
    eff = {}
    if "g_sensitivity_deg_h_per_g" in t:
        eff[("g_sensitivity", "gyro")] = ("G", [v * DEG_H / G0 for v in t["g_sensitivity_deg_h_per_g"]])
    if "gyro_bias_per_degC_deg_h" in t:
        eff[("temperature_bias", "gyro")] = ("per_degC", [v * DEG_H for v in t["gyro_bias_per_degC_deg_h"]])
    if "accel_bias_per_degC_mg" in t:
        eff[("temperature_bias", "accel")] = ("per_degC", [v * MG for v in t["accel_bias_per_degC_mg"]])
    if "time_offset_s" in t:
        eff[("time_offset", "both")] = ("tau_s", [t["time_offset_s"]])
    if "lever_arm_m" in t:
        eff[("lever_arm", "accel")] = ("r_m", list(t["lever_arm_m"]))
    if "mounting_misalignment_deg" in t:
        eff[("mounting_misalignment", "both")] = ("rotation_rad", [math.radians(v) for v in t["mounting_misalignment_deg"]])
    for sensor in ("gyro", "accel"):
        kp, kn = t.get(sensor + "_scale_asymmetry_pos_ppm"), t.get(sensor + "_scale_asymmetry_neg_ppm")
        if kp or kn:
            kp, kn = kp or [0, 0, 0], kn or [0, 0, 0]
            # The common part is the lab-calibrated scale; only k_pos - k_neg is concealed.
            eff[("scale_asymmetry", sensor)] = ("k_pos-k_neg", [1e-6 * (a - b) for a, b in zip(kp, kn)])
        unit = "_scale_nonlinearity_per_rad_s" if sensor == "gyro" else "_scale_nonlinearity_per_m_s2"
        if sensor + unit in t:
            eff[("scale_nonlinearity", sensor)] = ("k2", list(t[sensor + unit]))
    return eff

def as_list(v):
    return v if isinstance(v, list) else [v]

def param(e, pkey):
    """Estimate and 1-sigma of a parameter; k_pos-k_neg is the asymmetry of scale_asymmetry."""
    if pkey == "k_pos-k_neg":
        p, u = e["parameters"], e["uncertainty"]
        est = [a - b for a, b in zip(p["k_pos"], p["k_neg"])]
        sig = [math.hypot(a, b) for a, b in zip(u["k_pos"], u["k_neg"])]
        return est, sig
    return as_list(e["parameters"][pkey]), as_list(e["uncertainty"][pkey])

def fmt3(v):
    return "/".join(f"{x:.4g}" for x in v)

rows = []
for path in sorted(glob.glob(os.path.join(cfg_dir, "*.yaml"))):
    name = os.path.splitext(os.path.basename(path))[0]
    cfg = yaml.safe_load(open(path))
    inj = injected(cfg)
    jpath = os.path.join(out, name + "_diag", "diagnosis.json")
    if not os.path.exists(jpath):
        rows.append(f"| {name} | (diagnose failed, see {name}.diagnose.log) | | | | | |")
        continue
    j = json.load(open(jpath))
    found = {(e["name"], e["sensor"]): e for e in j["effects"]}
    errs = []
    for key, (pkey, truth) in inj.items():
        e = found.get(key)
        if e is None:
            errs.append(f"{key[0]}({key[1]}): not found")
            continue
        est, sig = param(e, pkey)
        z = [abs(a - b) / s if s else float("inf") for a, b, s in zip(est, truth, sig)]
        # Relative error over the elements the data determine (sigma below the true magnitude);
        # e.g. the g-sensitivity column of f_z (~ -g, constant) is confounded with the bias.
        det = [(a, b) for a, b, s in zip(est, truth, sig) if s is not None and s < abs(b)]
        txt = f"{key[0]}({key[1]}): max err/sigma {max(z):.1f}"
        if det:
            rel = math.sqrt(sum((a - b) ** 2 for a, b in det) / sum(b * b for _, b in det))
            txt += f", rel. error {100 * rel:.0f} % over {len(det)} of {len(truth)} determined elements"
        errs.append(txt)
    fit = j["fit"]
    rb, ra = fit["signal_rms_before"], fit["signal_rms_after"]
    sig_txt = (f"gyro {fmt3([x * 180 / math.pi for x in rb['gyro']])} -> {fmt3([x * 180 / math.pi for x in ra['gyro']])} deg/s; "
               f"accel {fmt3(rb['accel'])} -> {fmt3(ra['accel'])} m/s^2")
    def diff(d):
        if not d:
            return "n/a"
        return "/".join(f"{100 * d[k]:.0f}" if d[k] is not None else "-" for k in
                        ["horizontal_m", "vertical_m", "roll_deg", "pitch_deg", "heading_deg"])
    false_claims = [k for k in found if k not in inj]
    rows.append("| {} | {} | {} | {} | {} | {} | {} -> {} |".format(
        name,
        ", ".join(f"{k[0]}({k[1]})" for k in inj) or "none (null case)",
        ", ".join(f"{k[0]}({k[1]})" for k in found) or "none",
        ", ".join(f"{k[0]}({k[1]})" for k in false_claims) or "none",
        "; ".join(errs) or "-",
        sig_txt, diff(fit.get("diff_before")), diff(fit.get("diff_after"))))
print("| case | injected | found | false claims | parameter error | signal RMS before -> after | DIFF % h/v/roll/pitch/heading, SG2 -> SG3 |")
print("|---|---|---|---|---|---|---|")
for r in rows:
    print(r)
PYEOF
