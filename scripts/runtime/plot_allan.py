#!/usr/bin/env python3
"""Allan deviation plots with confidence bars and the fitted noise-term lines.

Usage: plot_allan.py OUT_DIR   (reads OUT_DIR/allan_gyro.csv and allan_accel.csv written by
`graftnav calibrate`, writes allan_gyro.png and allan_accel.png)

Lines: fitted model sqrt(N^2/tau + 0.4413 B^2 + K^2 tau/3) (solid), white-noise line N/sqrt(tau)
(slope -1/2, equals N at tau = 1 s), bias-instability floor 0.664 B, rate-random-walk line
K sqrt(tau/3) (slope +1/2, equals K at tau = 3 s).
"""
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    return {k: [float(r[k]) for r in rows] for k in rows[0]}


def plot(path_csv, path_png, gyro):
    d = read(path_csv)
    tau = d["tau_s"]
    scale = 180.0 / math.pi * 3600.0 if gyro else 1e3 / 9.80665
    unit = "deg/h" if gyro else "mg"
    fig, ax = plt.subplots(figsize=(7, 5))
    colors = {"x": "tab:red", "y": "tab:green", "z": "tab:blue"}
    for a, c in colors.items():
        adev = [v * scale for v in d["adev_" + a]]
        err = [v * r for v, r in zip(adev, d["rel_error"])]
        ax.errorbar(tau, adev, yerr=err, fmt="o", ms=3, color=c, label=f"{a} measured")
        ax.plot(tau, [v * scale for v in d["model_" + a]], "-", color=c, lw=1.5, label=f"{a} fit")
        N, B, K = d["N_" + a][0], d["B_" + a][0], d["K_" + a][0]
        if N > 0:
            ax.plot(tau, [N / math.sqrt(t) * scale for t in tau], ":", color=c, lw=0.8)
        if B > 0:
            ax.plot(tau, [0.664 * B * scale] * len(tau), "--", color=c, lw=0.8)
        if K > 0:
            ax.plot(tau, [K * math.sqrt(t / 3.0) * scale for t in tau], "-.", color=c, lw=0.8)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("cluster time tau (s)")
    ax.set_ylabel(f"Allan deviation ({unit})")
    ax.set_title(("Gyro" if gyro else "Accelerometer") +
                 " Allan deviation: fit (solid), N/sqrt(tau) (dotted), 0.664 B (dashed), K sqrt(tau/3) (dash-dot)",
                 fontsize=8)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7, ncol=3)
    fig.tight_layout()
    fig.savefig(path_png, dpi=120)
    plt.close(fig)


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "."
    for name, gyro in (("gyro", True), ("accel", False)):
        p = os.path.join(out, f"allan_{name}.csv")
        if os.path.exists(p):
            plot(p, os.path.join(out, f"allan_{name}.png"), gyro)


if __name__ == "__main__":
    main()
