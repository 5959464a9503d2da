#!/usr/bin/env python3
"""Plots of the real-data runs (docs/real-data.md).
  plot_real.py latency OUT_DIR PNG   -- OUT_DIR/latency_scan.csv of `graftnav real --latency-scan`
  plot_real.py sg OUT_DIR PNG        -- sol_ref.nav and solution_{REF,SG#1,REAL}.nav of `graftnav real-sg`
"""
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def latency(out, png):
    curves = {}
    with open(f"{out}/latency_scan.csv", newline="") as f:
        for r in csv.DictReader(f):
            key = f"fix {r['fix_type']} vs {r['track']}"
            curves.setdefault(key, ([], []))
            curves[key][0].append(float(r["shift_s"]))
            curves[key][1].append(float(r["rms_h_m"]))
    fig, ax = plt.subplots(figsize=(7, 4))
    for k, (x, y) in curves.items():
        ax.plot(x, y, label=k)
    ax.set_xlabel("trial latency tau (s): fix compared with the track at t_tag - tau")
    ax.set_ylabel("horizontal residual RMS (m)")
    ax.set_ylim(bottom=0)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    ax.set_title("yandld_20220405_rtk: GNSS time-tag latency scan")
    fig.tight_layout()
    fig.savefig(png, dpi=80)


def read_nav(path):
    rows = []
    with open(path) as f:
        for line in f:
            v = line.split()
            if len(v) >= 11:
                rows.append([float(x) for x in v[1:11]])
    return rows


def interp(rows, t, i0):
    while i0 + 1 < len(rows) and rows[i0 + 1][0] < t:
        i0 += 1
    if i0 + 1 >= len(rows) or rows[i0][0] > t:
        return None, i0
    a, b = rows[i0], rows[i0 + 1]
    u = (t - a[0]) / (b[0] - a[0])
    return [a[k] + u * (b[k] - a[k]) for k in range(len(a))], i0


def sg(out, png):
    ref = read_nav(f"{out}/sol_ref.nav")
    with open(f"{out}/outages.csv") as f:
        t0 = float(next(csv.DictReader(f))["data_start_s"])
    fig, ax = plt.subplots(figsize=(7, 4))
    for label in ["REF", "SG#1", "REAL"]:
        sol = read_nav(f"{out}/solution_{label}.nav")
        ts, eh = [], []
        i0 = 0
        for k in range(0, len(sol), 10):
            s = sol[k]
            r, i0 = interp(ref, s[0], i0)
            if r is None:
                continue
            dn = math.radians(s[1] - r[1]) * 6.371e6
            de = math.radians(s[2] - r[2]) * 6.371e6 * math.cos(math.radians(r[1]))
            ts.append(s[0] - t0)
            eh.append(math.hypot(dn, de))
        ax.plot(ts, eh, label=label, lw=1)
    with open(f"{out}/outages.csv") as f:
        for r in csv.DictReader(f):
            ax.axvspan(float(r["start_s"]) - t0, float(r["end_s"]) - t0, color="0.85")
    ax.set_xlabel(f"time since the first IMU epoch {t0:.1f} s")
    ax.set_ylabel("horizontal error vs SOL_REF (m)")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    ax.set_title("wid_car_trial07 (" + out.rstrip("/").split("_")[-1] + "): outages shaded")
    fig.tight_layout()
    fig.savefig(png, dpi=80)


if __name__ == "__main__":
    if len(sys.argv) != 4 or sys.argv[1] not in ("latency", "sg"):
        sys.exit(__doc__)
    {"latency": latency, "sg": sg}[sys.argv[1]](sys.argv[2], sys.argv[3])
