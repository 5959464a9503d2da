#!/usr/bin/env python3
"""Plots of `graftnav evaluate`: outage errors of SG1, SG2 (SG3) and REAL overlaid with the
outages shaded (the seed's Figs. 7-12), a bar chart of DIFF, and (with realizations) each
statistic's predictive interval with ERR_REAL marked (intervals.png).

usage: plot_sg.py OUT_DIR   (reads evaluation.json and errors_<LABEL>.csv written there)
"""
import csv
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

COLORS = {"SG1": "tab:blue", "SG2": "tab:orange", "SG3": "tab:green", "REAL": "black"}
# (evaluation.json key, errors_<LABEL>.csv column, axis title); vertical = |down|.
STATS = [("horizontal_m", "horizontal_m", "horizontal (m)"), ("vertical_m", "down_m", "vertical (m)"),
         ("roll_deg", "roll_deg", "roll (deg)"), ("pitch_deg", "pitch_deg", "pitch (deg)"),
         ("heading_deg", "heading_deg", "heading (deg)")]


def read_csv(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    # An empty cell (e.g. the NEES of an estimator without covariance) is not a number: NaN.
    return {k: [float(r[k]) if r[k] != "" else float("nan") for r in rows] for k in rows[0]} if rows else {}


def plot_intervals(ev, out):
    """One panel per statistic: SG#1's and SG#2's realizations (dots), their mean and 90 %
    interval (bar), and ERR_REAL (line), so a reader sees at once whether REAL falls inside."""
    pred = ev.get("predictive", {})
    if not pred or ev.get("realizations", 1) < 2:
        return
    real = ev.get("err", {}).get("REAL")
    sols = [s for s in ["SG1", "SG2"] if s in pred]
    fig, axes = plt.subplots(1, len(STATS), figsize=(14, 3.8))
    for ax, (key, _, title) in zip(axes, STATS):
        for i, s in enumerate(sols):
            q = pred[s][key]
            ax.errorbar([i], [q["mean"]], yerr=[[q["mean"] - q["p05"]], [q["p95"] - q["mean"]]], fmt="o",
                        color=COLORS[s], capsize=6, lw=2, label=f"{s} mean, 90 % interval")
            verdict = ev.get("verdict", {}).get(s, {}).get(key)
            if verdict:
                pct = ev["real_percentile"][s][key]
                ax.annotate(f"REAL at {100 * pct:.0f} %\n{verdict}", (i, q["p95"]), textcoords="offset points",
                            xytext=(0, 8), ha="center", fontsize=8)
        if real and real.get(key) is not None:
            ax.axhline(real[key], color="black", lw=1.5, ls="--", label="ERR_REAL")
        ax.set_xticks(range(len(sols)))
        ax.set_xticklabels([f"SG#{s[2:]}" for s in sols])
        ax.set_xlim(-0.6, len(sols) - 0.4)
        ax.set_title(title)
        ax.grid(axis="y", alpha=0.3)
        ax.margins(y=0.25)
    handles, names = axes[0].get_legend_handles_labels()
    fig.legend(handles, names, loc="lower center", ncol=len(names), fontsize=8)
    fig.suptitle(f"{ev['case']}: ERR of {ev['realizations']} grafted realizations against ERR_REAL ({ev['estimator']})")
    fig.tight_layout(rect=(0, 0.07, 1, 1))
    fig.savefig(os.path.join(out, "intervals.png"), dpi=110)
    plt.close(fig)


def main(out):
    with open(os.path.join(out, "evaluation.json")) as f:
        ev = json.load(f)
    windows = ev.get("outage_windows_s", [])
    labels = [l for l in ["SG1", "SG2", "SG3", "REAL"] if os.path.exists(os.path.join(out, f"errors_{l}.csv"))]
    data = {l: read_csv(os.path.join(out, f"errors_{l}.csv")) for l in labels}
    t0 = min(d["t_s"][0] for d in data.values() if d)

    fig, axes = plt.subplots(len(STATS), 1, figsize=(11, 11), sharex=True)
    for ax, (_, column, title) in zip(axes, STATS):
        for w in windows:
            ax.axvspan(w[0] - t0, w[1] - t0, color="cyan", alpha=0.2, lw=0)
        for l in labels:
            d = data[l]
            # Only epochs inside outages: between them every solution sits at the GNSS level.
            xs, ys = [], []
            for t, v, o in zip(d["t_s"], d[column], d["outage"]):
                if o >= 0:
                    xs.append(t - t0)
                    ys.append(abs(v))
                else:
                    xs.append(t - t0)
                    ys.append(float("nan"))
            ax.plot(xs, ys, color=COLORS.get(l, None), lw=1.0, label=l)
        ax.set_ylabel(title)
        ax.grid(alpha=0.3)
    axes[0].legend(loc="upper left", ncol=len(labels))
    axes[-1].set_xlabel(f"time since {t0:.0f} s of week (s); outages shaded")
    fig.suptitle(f"{ev['case']}: errors against SOL_REF in GNSS outages ({ev['estimator']})")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "outage_errors.png"), dpi=110)
    plt.close(fig)

    plot_intervals(ev, out)

    if "diff" in ev:
        fig, ax = plt.subplots(figsize=(8, 4))
        keys = [k for k, _, _ in STATS]
        sols = list(ev["diff"].keys())
        width = 0.8 / max(len(sols), 1)
        for i, s in enumerate(sols):
            vals = [100.0 * (ev["diff"][s][k] if ev["diff"][s][k] is not None else float("nan")) for k in keys]
            ax.bar([j + i * width for j in range(len(keys))], vals, width, label=f"DIFF_{s[2:]}",
                   color=COLORS.get(s, None))
        ax.set_xticks([j + width * (len(sols) - 1) / 2 for j in range(len(keys))])
        ax.set_xticklabels([t for _, _, t in STATS])
        ax.set_ylabel("|ERR_x - ERR_REAL| / ERR_REAL (%)")
        ax.legend()
        ax.grid(axis="y", alpha=0.3)
        ax.set_title(f"{ev['case']}: how close grafting came to the real IMU")
        fig.tight_layout()
        fig.savefig(os.path.join(out, "diff.png"), dpi=110)
        plt.close(fig)


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
