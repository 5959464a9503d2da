#!/usr/bin/env python3
"""The Markdown tables of run_concealed_suite.sh: per concealed-effects case the effect injected and
found, parameter errors and the fit before/after; with seeds, detection rates and false claims
pooled over the Monte-Carlo runs.

Usage: concealed_suite_table.py CFG_DIR RESULT_DIR N_SEEDS ESTIMATOR CFG.yaml...
"""
import glob, json, math, os, statistics, sys
import yaml

cfg_dir, out, n_seeds, estimator = sys.argv[1], sys.argv[2], int(sys.argv[3]), sys.argv[4]
cfg_paths = sys.argv[5:]
DEG_H = math.pi / 180.0 / 3600.0   # deg/h -> rad/s
G0 = 9.80665
MG = 1e-3 * G0
STATS = ["horizontal_m", "vertical_m", "roll_deg", "pitch_deg", "heading_deg"]

def numbers(node):
    """A YAML node's numbers as floats: PyYAML reads 1e-06 (no decimal point, YAML 1.1) as a
    string, which the simulator's YAML 1.2 parser reads as a number."""
    if isinstance(node, dict):
        return {k: numbers(v) for k, v in node.items()}
    if isinstance(node, list):
        return [numbers(v) for v in node]
    if isinstance(node, str):
        try:
            return float(node)
        except ValueError:
            return node
    return node

def injected(cfg):
    """Injected effects {(name, sensor): (parameter key, true values)} in diagnosis.json's terms."""
    t = numbers(cfg.get("tested_imu", {}))
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
            # The mean gain (k_pos + k_neg) / 2 is the lab-calibrated scale, in the simulation;
            # what is concealed, and what diagnose reports as k_pos / k_neg (gains relative to
            # the simulation's), is +-(k_pos - k_neg) / 2 about it: compared element by element.
            m = [0.5e-6 * (a + b) for a, b in zip(kp, kn)]
            eff[("scale_asymmetry", sensor)] = (
                "k_pos,k_neg", [1e-6 * a - c for a, c in zip(kp, m)] + [1e-6 * b - c for b, c in zip(kn, m)])
        unit = "_scale_nonlinearity_per_rad_s" if sensor == "gyro" else "_scale_nonlinearity_per_m_s2"
        if sensor + unit in t:
            eff[("scale_nonlinearity", sensor)] = ("k2", list(t[sensor + unit]))
        vib = t.get(sensor + "_vibration_rectification")
        if vib:
            reg = vib.get("regressor", "specific_force_hp_sq")
            eff[("vibration_rectification", sensor)] = ("coeff@" + reg, list(vib["coeff"]))
        qkey = sensor + ("_quantization_rad" if sensor == "gyro" else "_quantization_m_s")
        if qkey in t:
            q = t[qkey]
            eff[("quantization", sensor)] = ("step", list(q) if isinstance(q, list) else [q] * 3)
    return eff

def injected_in_case(name, path):
    """Concealed effects of a case: none for null* cases, whose tested IMU may carry terms that
    grafting models (e.g. a gyro non-linearity the lab fitting functions recover)."""
    return {} if name.startswith("null") else injected(yaml.safe_load(open(path)))

def reference_scale(diag_dir):
    """{sensor: k} of the reference IMU's own scale factor as the simulator drew it
    (simulation.yaml, copied next to diagnosis.json), {} when unknown."""
    path = os.path.join(diag_dir, "simulation.yaml")
    if not os.path.exists(path):
        return {}
    out = {}
    for e in yaml.safe_load(open(path)).get("reference_imu_errors", []) or []:
        if e.get("term") == "scale_factor":
            txt = e["parameters"]
            out[e["sensor"]] = [float(v) for v in txt[txt.index("[") + 1:txt.index("]")].split(",")]
    return out

def reference_own(key, e, ref):
    """True when a claim not injected is the reference IMU's own scale error seen from the tested
    side: the simulation is built on the reference signal, so it carries k_ref and the real tested
    IMU does not; the residual shows -k_ref (within 3 sigma or 20 %, as an injected effect)."""
    if key[0] != "scale_factor" or key[1] not in ref:
        return False
    pe = param_error(e, "k", [-v for v in ref[key[1]]])
    return pe is not None and (pe[0] <= 3.0 or (pe[1] is not None and pe[1] <= 0.2))

def reference_own_claims(found, inj, diag_dir):
    """The claims in `found` not injected that are the reference IMU's own scale error."""
    ref = reference_scale(diag_dir)
    return {k for k in found if k not in inj and reference_own(k, found[k], ref)}

def as_list(v):
    return v if isinstance(v, list) else [v]

def param(e, pkey):
    """Estimate and 1-sigma of a parameter; "a,b" are parameters a and b in one list (k_pos and
    k_neg of scale_asymmetry); coeff@REG is the vibration coefficient, None if the found
    regressor is another one."""
    p, u = e["parameters"], e["uncertainty"]
    if "," in pkey:
        est, sig = [], []
        for k in pkey.split(","):
            est += as_list(p[k])
            sig += [s if s is not None else float("inf") for s in as_list(u[k])]
        return est, sig
    if pkey.startswith("coeff@"):
        if p.get("regressor") != pkey.split("@", 1)[1]:
            return None
        pkey = "coeff"
    return as_list(p[pkey]), [s if s is not None else float("inf") for s in as_list(u[pkey])]

def param_error(e, pkey, truth):
    """(max |err|/sigma, relative error over the determined elements, n determined, z list) or
    None when the parameter is not comparable (other vibration regressor)."""
    r = param(e, pkey)
    if r is None:
        return None
    est, sig = r
    z = [abs(a - b) / s if s else float("inf") for a, b, s in zip(est, truth, sig)]
    # Relative error over the elements the data determine (sigma below the true magnitude);
    # e.g. the g-sensitivity column of f_z (~ -g, constant) is confounded with the bias.
    det = [(a, b, s) for a, b, s in zip(est, truth, sig) if s is not None and s < abs(b)]
    rel = None
    if det:
        rel = math.sqrt(sum((a - b) ** 2 for a, b, _ in det) / sum(b * b for _, b, _ in det))
    zdet = [abs(a - b) / s for a, b, s in det if s]
    return max(z), rel, len(det), zdet

def fmt3(v):
    return "/".join(f"{x:.4g}" for x in v)

def load(jpath):
    return json.load(open(jpath)) if os.path.exists(jpath) else None

def diff(d):
    if not d:
        return "n/a"
    return "/".join(f"{100 * d[k]:.0f}" if d.get(k) is not None else "-" for k in STATS)

def label(k):
    return f"{k[0]}({k[1]})"

def limit_ratio(j, key, pkey, truth):
    """", truth/limit R" for a missed effect: the largest ratio of a true element to the
    detection limit the finder stated for it (R < 1: below the stated limit)."""
    r = limit_ratio_value(j, key, pkey, truth)
    return f", truth/limit {r:.2g}" if r is not None else ""

def limit_ratio_value(j, key, pkey, truth):
    """The largest ratio of a true element to the stated detection limit, None without one."""
    for d in j.get("detection_limits", []):
        if (d["name"], d["sensor"]) != key:
            continue
        # A gyro has two vibration levels: the limit is the injected regressor's.
        if pkey.startswith("coeff@") and d.get("regressor", pkey.split("@", 1)[1]) != pkey.split("@", 1)[1]:
            continue
        lim = d["limit"]
        if "," in pkey:
            lim = sum((as_list(lim.get(k, [])) for k in pkey.split(",")), []) or None
        elif pkey.startswith("coeff@"):
            lim = lim.get("coeff")
        else:
            lim = lim.get(pkey)
        if lim is None:
            return None
        r = [abs(t) / abs(l) for t, l in zip(truth, as_list(lim)) if l]
        return max(r) if r else None
    return None

def in_simulation(j):
    """Effects the diagnosis lists as already in the simulation (the lab's quadratic in SG#2)."""
    return {(e["name"], e["sensor"]): e for e in j.get("modelled_in_simulation", [])}

def lab_text(e, pkey, truth):
    est, sig = param(e, pkey)
    return "lab " + "/".join(f"{a:.3g}" + (f"+-{s:.2g}" if s != float("inf") else "") for a, s in zip(est, sig)) + \
        ", injected " + fmt3(truth)

def ambiguous_text(j, key):
    """An effect found but listed under 'ambiguous' (its shape not settled against another)."""
    for a in j.get("ambiguous", []):
        if key in ((a["name"], a["sensor"]), (a["alternative"], a["sensor"])):
            return (f" (ambiguous: fitted as {a['name']}, or {a['alternative']}, "
                    f"margin {a['evidence']['name_margin']:.1f})")
    return ""


def single_table():
    rows = []
    for path in cfg_paths:
        name = os.path.splitext(os.path.basename(path))[0]
        inj = injected_in_case(name, path)
        j = load(os.path.join(out, name + "_diag", "diagnosis.json"))
        if j is None:
            rows.append(f"| {name} | (diagnose failed, see {name}.diagnose.log) | | | | | |")
            continue
        found = {(e["name"], e["sensor"]): e for e in j["effects"]}
        lab = in_simulation(j)
        errs = []
        for key, (pkey, truth) in inj.items():
            e = found.get(key)
            if e is None and key in lab:
                errs.append(f"{label(key)}: not claimed, in SG#2 from the lab ({lab_text(lab[key], pkey, truth)})")
                continue
            if e is None:
                errs.append(f"{label(key)}: not found" + limit_ratio(j, key, pkey, truth) +
                            ambiguous_text(j, key))
                continue
            pe = param_error(e, pkey, truth)
            if pe is None:
                errs.append(f"{label(key)}: found with regressor {e['parameters'].get('regressor')}")
                continue
            zmax, rel, ndet, _ = pe
            txt = f"{label(key)}: max err/sigma {zmax:.1f}"
            if rel is not None:
                txt += f", rel. error {100 * rel:.0f} % over {ndet} of {len(truth)} determined elements"
            errs.append(txt)
        fit = j["fit"]
        rb, ra = fit["signal_rms_before"], fit["signal_rms_after"]
        sig_txt = (f"gyro {fmt3([x * 180 / math.pi for x in rb['gyro']])} -> {fmt3([x * 180 / math.pi for x in ra['gyro']])} deg/s; "
                   f"accel {fmt3(rb['accel'])} -> {fmt3(ra['accel'])} m/s^2")
        own = reference_own_claims(found, inj, os.path.join(out, name + "_diag"))
        false_claims = [k for k in found if k not in inj and k not in own]
        rows.append("| {} | {} | {} | {} | {} | {} | {} -> {} |".format(
            name,
            ", ".join(label(k) for k in inj) or "none (null case)",
            ", ".join(label(k) + (" [the reference IMU's own scale error]" if k in own else "")
                      for k in found) or "none",
            ", ".join(label(k) for k in false_claims) or "none",
            "; ".join(errs) or "-",
            sig_txt, diff(fit.get("diff_before")), diff(fit.get("diff_after"))))
    print(f"| case | injected | found | false claims | parameter error | signal RMS before -> after | DIFF % h/v/roll/pitch/heading, SG2 -> SG3 ({estimator}) |")
    print("|---|---|---|---|---|---|---|")
    for r in rows:
        print(r)

def quantile(v, q):
    v = sorted(v)
    if not v:
        return float("nan")
    x = q * (len(v) - 1)
    i = int(math.floor(x))
    return v[i] if i + 1 >= len(v) else v[i] + (x - i) * (v[i + 1] - v[i])

def diff_of_means(runs, est):
    """DIFF of the mean ERR over seeds: |mean ERR_est - mean ERR_REAL| / mean ERR_REAL."""
    out = {}
    for k in STATS:
        a = [r["err"][est][k] for r in runs]
        b = [r["err"]["REAL"][k] for r in runs]
        out[k] = abs(statistics.fmean(a) - statistics.fmean(b)) / statistics.fmean(b)
    return out

def bootstrap_sd(runs, est, n_boot=400):
    """Bootstrap (over seeds) standard deviation of the DIFF of means, per statistic."""
    import random
    rng = random.Random(12345)
    vals = {k: [] for k in STATS}
    for _ in range(n_boot):
        smp = [runs[rng.randrange(len(runs))] for _ in runs]
        d = diff_of_means(smp, est)
        for k in STATS:
            vals[k].append(d[k])
    return {k: statistics.pstdev(vals[k]) for k in STATS}

def pct(d, sd=None):
    if sd is None:
        return "/".join(f"{100 * d[k]:.0f}" for k in STATS)
    return "/".join(f"{100 * d[k]:.0f}±{100 * sd[k]:.0f}" for k in STATS)

def mc_tables():
    det_rows, diff_rows = [], []
    for path in cfg_paths:
        name = os.path.splitext(os.path.basename(path))[0]
        inj = injected_in_case(name, path)
        runs = []
        for jp in sorted(glob.glob(os.path.join(out, name, "s*_diag", "diagnosis.json"))):
            j = load(jp)
            if j is None:
                continue
            fit = j.get("fit", {})
            found = {(e["name"], e["sensor"]): e for e in j["effects"]}
            runs.append({"found": found, "json": j,
                         "own": reference_own_claims(found, inj, os.path.dirname(jp)),
                         "lab": in_simulation(j),
                         "err": fit.get("err"), "db": fit.get("diff_before"), "da": fit.get("diff_after")})
        n = len(runs)
        if n == 0:
            det_rows.append(f"| {name} | 0 | (no diagnosis.json) | | |")
            continue
        det, errs = [], []
        for key, (pkey, truth) in inj.items():
            hits = [r["found"][key] for r in runs if key in r["found"]]
            n_lab = sum(1 for r in runs if key not in r["found"] and key in r["lab"])
            # Runs that missed it although it was above the limit the finder stated (a miss below
            # the stated limit is the limit's to explain, not a failed detection).
            above = [r for r in runs if key not in r["found"] and key not in r["lab"]
                     and (limit_ratio_value(r["json"], key, pkey, truth) or 0.0) >= 1.0]
            det.append(f"{label(key)} {len(hits)}/{n}" + (f" (+{n_lab} in SG#2 from the lab)" if n_lab else "")
                       + (f" [missed above its stated limit: {len(above)}]" if above else ""))
            zs, rels, within = [], [], 0
            for e in hits:
                pe = param_error(e, pkey, truth)
                if pe is None:
                    continue
                zmax, rel, _, zdet = pe
                zs += zdet
                if rel is not None:
                    rels.append(rel)
                if zmax <= 3.0 or (rel is not None and rel <= 0.2):
                    within += 1
            if hits:
                txt = f"{label(key)}: {within}/{len(hits)} within 3 sigma or 20 %"
                if rels:
                    txt += f", median rel. error {100 * statistics.median(rels):.0f} %"
                if zs:
                    txt += f", RMS err/sigma {math.sqrt(sum(z * z for z in zs) / len(zs)):.1f}"
                errs.append(txt)
        fc, n_own = {}, 0
        for r in runs:
            n_own += len(r["own"])
            for k in r["found"]:
                if k not in inj and k not in r["own"]:
                    fc[k] = fc.get(k, 0) + 1
        n_any = sum(1 for r in runs if any(k not in inj and k not in r["own"] for k in r["found"]))
        fc_txt = (f"{n_any}/{n} runs: " + ", ".join(f"{label(k)} {c}" for k, c in sorted(fc.items()))) if fc else f"0/{n}"
        if n_own:
            fc_txt += f" (+{n_own} claims of the reference IMU's own scale error)"
        det_rows.append("| {} | {} | {} | {} | {} |".format(
            name, n, ", ".join(det) or "none (null case)", fc_txt, "; ".join(errs) or "-"))
        nav = [r for r in runs if r["err"] and all(s in r["err"] for s in ("SG2", "SG3", "REAL"))]
        if not nav:
            diff_rows.append(f"| {name} | 0 | n/a | n/a | n/a | n/a |")
            continue
        dm2, dm3 = diff_of_means(nav, "SG2"), diff_of_means(nav, "SG3")
        sd2, sd3 = bootstrap_sd(nav, "SG2"), bootstrap_sd(nav, "SG3")
        med = lambda key: {k: statistics.median(r[key][k] for r in nav) for k in STATS}
        p90 = lambda key: {k: quantile([r[key][k] for r in nav], 0.9) for k in STATS}
        mean_err = lambda est: "/".join(f"{statistics.fmean(r['err'][est][k] for r in nav):.3g}" for k in STATS)
        diff_rows.append("| {} | {} | {} / {} / {} | {} -> {} | {} -> {} | {} -> {} |".format(
            name, len(nav), mean_err("SG2"), mean_err("SG3"), mean_err("REAL"),
            pct(dm2, sd2), pct(dm3, sd3), pct(med("db")), pct(med("da")), pct(p90("db")), pct(p90("da"))))
    print(f"Monte Carlo over seeds ({estimator}): detection and parameters\n")
    print("| case | seeds | injected: found in | false claims (runs with any; per effect) | parameter error over the runs that found it |")
    print("|---|---|---|---|---|")
    for r in det_rows:
        print(r)
    print(f"\nMonte Carlo over seeds ({estimator}): navigation level, statistics h/v/roll/pitch/heading "
          "(m, m, deg, deg, deg); DIFF in %\n")
    print("| case | seeds | mean ERR SG2 / SG3 / REAL | DIFF of mean ERR (± bootstrap sd), SG2 -> SG3 | single-run DIFF median, SG2 -> SG3 | single-run DIFF 90 % quantile, SG2 -> SG3 |")
    print("|---|---|---|---|---|---|")
    for r in diff_rows:
        print(r)

if n_seeds == 0:
    single_table()
else:
    mc_tables()
