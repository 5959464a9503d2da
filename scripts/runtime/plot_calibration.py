#!/usr/bin/env python3
"""Calibration plots: per-axis fitting functions (Eq. 21) with their residuals, and |f| at rest
per pose before/after calibration.

Usage: plot_calibration.py OUT_DIR   (reads fit_gyro.csv, fit_accel.csv, pose_norms.csv written by
`graftnav calibrate`; writes fit_gyro.png, fit_accel.png, pose_norms.png)
"""
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def rows(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def plot_fit(path_csv, path_png, gyro):
    r = rows(path_csv)
    xs_scale = 180.0 / math.pi if gyro else 1.0
    unit = "deg/s" if gyro else "m/s^2"
    fig, axes = plt.subplots(2, 3, figsize=(11, 6), sharex="col")
    for a in range(3):
        pts = sorted((float(q["x_true"]), float(q["y_measured_own_axis"]), float(q["fit"]), float(q["linear_M"]),
                      float(q.get("sigma_with_drift") or q["sigma"]))
                     for q in r if int(q["axis"]) == a)
        x = [p[0] * xs_scale for p in pts]
        axes[0][a].plot(x, [p[1] * xs_scale for p in pts], "o", ms=4, label="measured (cross-axis removed)")
        axes[0][a].plot(x, [p[2] * xs_scale for p in pts], "-", label="fitting function")
        axes[0][a].set_title(f"{'gyro' if gyro else 'accel'} {'xyz'[a]}")
        axes[1][a].errorbar(x, [(p[1] - p[2]) * xs_scale for p in pts], yerr=[p[4] * xs_scale for p in pts],
                            fmt="o", ms=4, capsize=2, label="meas - fit (1 sigma incl. pose drift)")
        axes[1][a].plot(x, [(p[1] - p[3]) * xs_scale for p in pts], "x", ms=4, label="meas - (M_ii x + b)")
        axes[1][a].set_xlabel(f"theoretical ({unit})")
        axes[1][a].grid(True, alpha=0.3)
        axes[0][a].grid(True, alpha=0.3)
    axes[0][0].set_ylabel(f"measured ({unit})")
    axes[1][0].set_ylabel(f"residual ({unit})")
    axes[0][0].legend(fontsize=7)
    axes[1][0].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path_png, dpi=110)
    plt.close(fig)


def plot_norms(path_csv, path_png):
    r = rows(path_csv)
    names = [q["pose"] for q in r]
    g = float(r[0]["gravity"])
    raw = [float(q["raw_norm"]) - g for q in r]
    cal = [float(q["calibrated_norm"]) - g for q in r]
    fig, ax = plt.subplots(figsize=(7, 4))
    idx = range(len(names))
    ax.bar([i - 0.2 for i in idx], raw, 0.4, label="raw")
    ax.bar([i + 0.2 for i in idx], cal, 0.4, label="calibrated")
    ax.set_xticks(list(idx))
    ax.set_xticklabels(names, rotation=30, fontsize=8)
    ax.set_ylabel("|f| - g at rest (m/s^2)")
    ax.axhline(0.0, color="k", lw=0.5)
    ax.legend()
    ax.grid(True, axis="y", alpha=0.3)
    fig.tight_layout()
    fig.savefig(path_png, dpi=110)
    plt.close(fig)


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "."
    for name, gyro in (("gyro", True), ("accel", False)):
        p = os.path.join(out, f"fit_{name}.csv")
        if os.path.exists(p):
            plot_fit(p, os.path.join(out, f"fit_{name}.png"), gyro)
    p = os.path.join(out, "pose_norms.csv")
    if os.path.exists(p):
        plot_norms(p, os.path.join(out, "pose_norms.png"))


if __name__ == "__main__":
    main()
