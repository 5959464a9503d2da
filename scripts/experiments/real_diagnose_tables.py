#!/usr/bin/env python3
"""Writes the mismatch finder's result tables for the real two-IMU recordings into
docs/results/real_diagnose.md, from the current code: for every case under the real-data folder
that has both field/ref_imu.txt and field/tested_imu.txt it runs `graftnav diagnose CASE --out
OUT/NAME --no-plots` and tabulates diagnosis.json (claimed, fitted but implausible for the sensor
class, correlations between fitted terms, the excitation a split of mounting / scale /
non-orthogonality would need, the value lattice, residual RMS and the held-out check).

Usage: scripts/experiments/real_diagnose_tables.py [--data DIR] [--binary build/graftnav] [--out DOC]
                                       [--work DIR]
  --data    the real-data folder (default: $GRAFTNAV_REAL_DATA or ../shared/data/real)
  --out     the Markdown file written (default docs/results/real_diagnose.md)
  --work    where the diagnoses go (default /tmp/graftnav_real_diagnose)
The pinned test tests/apps/test_diagnose_real_pinned.cpp checks the same numbers within
tolerance; a change of either is a reviewed change.
"""
import argparse
import json
import math
import os
import subprocess
import sys

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
RAD2DEG = 180.0 / math.pi


def fmt(v, digits=4):
    if v is None:
        return "-"
    if isinstance(v, list):
        return "[" + ", ".join(fmt(x, digits) for x in v) + "]"
    return f"{v:.{digits}g}"


def params_cell(e):
    out = []
    for k, v in e["parameters"].items():
        if isinstance(v, str):
            out.append(f"{k} = {v}")
            continue
        s = e["uncertainty"].get(k)
        out.append(f"{k} = {fmt(v)} +- {fmt(s, 2)}")
    return "; ".join(out)


def rms_cell(r, sensor):
    k = RAD2DEG if sensor == "gyro" else 1.0
    return " / ".join(f"{x * k:.4f}" for x in r[sensor])


def case_tables(name, j, command):
    m = [f"## {name}", "", f"Command: `{command}`", "",
         f"Simulation: {j['simulation']}.", ""]
    pr = j.get("plausible_ranges")
    if pr:
        m += [f"Plausible ranges: class `{pr['sensor_class']}` ({pr['source']}).", ""]
    m += ["### Claimed", "", "| effect | sensor | parameters (SI) +- 1-sigma | delta BIC | cv gain |",
          "|---|---|---|---|---|"]
    for e in j["effects"]:
        ev = e["evidence"]
        m.append(f"| {e['name']} | {e['sensor']} | {params_cell(e)} | {fmt(ev.get('delta_bic'), 6)} | "
                 f"{fmt(ev.get('cv_gain'), 3)} |")
    if not j["effects"]:
        m.append("| (none) | | | | |")
    m += ["", "### Fitted, implausible for the sensor class (modelled in SG#3, not claimed)", "",
          "| term | sensor | largest value | bound | probably absorbing (canonical correlation) |",
          "|---|---|---|---|---|"]
    for e in j.get("implausible", []):
        r = e["range"]
        ab = e.get("probably_absorbing")
        m.append(f"| {e['name']} | {e['sensor']} | {r['parameter']} {fmt(r['max_abs_value'], 3)} | "
                 f"{fmt(r['bound'], 3)} | {ab + ' (' + fmt(e['correlation'], 3) + ')' if ab else 'a signal outside the candidate terms'} |")
    if not j.get("implausible"):
        m.append("| (none) | | | | |")
    lin = [e for e in j["effects"] + j.get("implausible", []) if e["name"] == "mounting_scale_nonorthogonality"]
    if lin:
        e = lin[0]
        m += ["", "Mounting rotation, scale and non-orthogonality as one linear response "
              "(row-major E per sensor, r = E x):", ""]
        for k in ("E_gyro", "E_accel"):
            v, s = e["parameters"][k], e["uncertainty"][k]
            m.append(f"- {k}: " + "; ".join(fmt(v[3 * i:3 * i + 3], 3) for i in range(3)) +
                     " (1-sigma " + "; ".join(fmt(s[3 * i:3 * i + 3], 2) for i in range(3)) + ")")
    sep = j.get("separation_needed")
    if sep:
        m += ["", "### What would separate mounting, scale and non-orthogonality", "",
              "| | roll | pitch |", "|---|---|---|",
              f"| gyro: seconds needed at {sep['rate_deg_s']:.0f} deg/s RMS | {fmt(sep['roll_rate_s'], 3)} | {fmt(sep['pitch_rate_s'], 3)} |",
              f"| gyro: this record's equivalent (after the terms' correlation) | {fmt(sep['roll_rate_present_s'], 3)} | {fmt(sep['pitch_rate_present_s'], 3)} |",
              f"| accel: seconds held at {sep['tilt_deg']:.0f} deg | {fmt(sep['roll_tilt_s'], 3)} | {fmt(sep['pitch_tilt_s'], 3)} |",
              "", f"(each matrix column to a third of the class's non-orthogonality bound, "
              f"{sep['nonorthogonality_bound_deg']:.3g} deg; noise-limited, so a lower bound)"]
    corr = sorted(j.get("term_correlations", []), key=lambda c: -c["canonical_correlation"])
    m += ["", "### Correlation between fitted terms (largest canonical correlation; > 0.5 shown)", "",
          "| term | term | correlation |", "|---|---|---|"]
    shown = [c for c in corr if c["canonical_correlation"] > 0.5]
    for c in shown:
        m.append(f"| {c['a']} | {c['b']} | {c['canonical_correlation']:.3f} |")
    if not shown:
        m.append("| (none above 0.5) | | |")
    m += ["", "### Value lattice of the tested increments", "",
          "| sensor | step | printed resolution | q^2/12 over white noise | resolvable from | claimed |",
          "|---|---|---|---|---|---|"]
    for q in j.get("quantization_checks", []):
        m.append(f"| {q['sensor']} | {fmt(q['step'], 3)} | {fmt(q['printed_resolution'], 3)} | "
                 f"{fmt(q['noise_share'], 3)} | {fmt(q['resolvable_share'], 3)} | {q['claimed']} |")
    f = j["fit"]
    m += ["", "### Residual RMS (gyro deg/s x / y / z; accel m/s^2 x / y / z)", "",
          "| | gyro | accel |", "|---|---|---|",
          f"| before the model | {rms_cell(f['signal_rms_before'], 'gyro')} | {rms_cell(f['signal_rms_before'], 'accel')} |",
          f"| after | {rms_cell(f['signal_rms_after'], 'gyro')} | {rms_cell(f['signal_rms_after'], 'accel')} |"]
    h = f.get("holdout")
    if h:
        m += [f"| second half, before (model fitted on the first half, split t = {h['split_t']:.2f}) | "
              f"{rms_cell(h['second_half_rms_before'], 'gyro')} | {rms_cell(h['second_half_rms_before'], 'accel')} |",
              f"| second half, after | {rms_cell(h['second_half_rms_after'], 'gyro')} | "
              f"{rms_cell(h['second_half_rms_after'], 'accel')} |"]
    return m + [""]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--data", default=os.environ.get(
        "GRAFTNAV_REAL_DATA", os.path.join(os.path.dirname(REPO), "shared", "data", "real")))
    ap.add_argument("--binary", default=os.path.join(REPO, "build", "graftnav"))
    ap.add_argument("--out", default=os.path.join(REPO, "docs", "results", "real_diagnose.md"))
    ap.add_argument("--work", default="/tmp/graftnav_real_diagnose")
    a = ap.parse_args()
    cases = sorted(d for d in os.listdir(a.data)
                   if os.path.isfile(os.path.join(a.data, d, "field", "ref_imu.txt"))
                   and os.path.isfile(os.path.join(a.data, d, "field", "tested_imu.txt")))
    if not cases:
        sys.exit(f"no two-IMU case under {a.data}")
    commit = subprocess.run(["git", "-C", REPO, "rev-parse", "--short", "HEAD"],
                            capture_output=True, text=True).stdout.strip()
    lines = ["# `graftnav diagnose` on the real two-IMU recordings", "",
             "Written by `scripts/experiments/real_diagnose_tables.py` (do not edit by hand) from the code at "
             f"commit {commit or 'unknown'}; tests/apps/test_diagnose_real_pinned.cpp pins the "
             "same results within tolerance.", ""]
    for name in cases:
        out = os.path.join(a.work, name)
        cmd = [a.binary, "diagnose", os.path.join(a.data, name), "--out", out, "--no-plots"]
        subprocess.run(cmd, check=True, capture_output=True)
        with open(os.path.join(out, "diagnosis.json")) as f:
            j = json.load(f)
        shown = f"graftnav diagnose ../shared/data/real/{name} --out OUT --no-plots"
        lines += case_tables(name, j, shown)
    os.makedirs(os.path.dirname(a.out), exist_ok=True)
    with open(a.out, "w") as f:
        f.write("\n".join(lines))
    print(f"wrote {a.out} ({len(cases)} case(s))")


if __name__ == "__main__":
    main()
