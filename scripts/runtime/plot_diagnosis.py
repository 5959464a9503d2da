#!/usr/bin/env python3
"""Plots of `graftnav diagnose`: residual real - simulated per channel without and with the model.

Usage: plot_diagnosis.py OUT_DIR   (reads OUT_DIR/residual.csv [and outages.csv], writes
OUT_DIR/diagnosis_residual.png [and diagnosis_outages.png: per-outage drift of SG#2, SG#3, REAL])."""
import csv
import json
import os
import sys
import textwrap

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

CH = ["gyro_x", "gyro_y", "gyro_z", "accel_x", "accel_y", "accel_z"]
KEYS = ["gx", "gy", "gz", "ax", "ay", "az"]


def main(out_dir):
    rows = list(csv.DictReader(open(os.path.join(out_dir, "residual.csv"))))
    if not rows:
        print("plot_diagnosis: empty residual.csv", file=sys.stderr)
        return 1
    t0 = float(rows[0]["t_s"])
    t = [float(r["t_s"]) - t0 for r in rows]
    fig, axes = plt.subplots(6, 1, figsize=(11, 13), sharex=True)
    for i, (ch, k) in enumerate(zip(CH, KEYS)):
        scale = 180.0 / 3.141592653589793 if i < 3 else 1.0
        unit = "deg/s" if i < 3 else "m/s^2"
        r = [float(x["r_" + k]) for x in rows]
        c = [float(x["c_" + k]) for x in rows]
        m = [float(x["m_" + k]) for x in rows]
        mean = sum(r) / len(r)
        before = [(v - mean) * scale for v in r]
        after = [(v - cc - mm) * scale for v, cc, mm in zip(r, c, m)]
        model = [(mm + cc - mean) * scale for mm, cc in zip(m, c)]
        ax = axes[i]
        ax.plot(t, before, lw=0.5, color="tab:red", label="residual (constant removed)")
        ax.plot(t, model, lw=0.5, color="0.4", alpha=0.7, label="model")
        ax.plot(t, after, lw=0.5, color="tab:blue", label="residual after model")
        ax.set_ylabel(f"{ch}\n[{unit}]")
        ax.grid(alpha=0.3)
    axes[0].legend(loc="upper right", fontsize=8, ncol=3)
    axes[-1].set_xlabel(f"time since {t0:.2f} s [s]")
    title = "real - simulated"
    jpath = os.path.join(out_dir, "diagnosis.json")
    if os.path.exists(jpath):
        j = json.load(open(jpath))
        names = ", ".join(e["name"] + "(" + e["sensor"] + ")" for e in j.get("effects", []))
        title = f"{j.get('case', '')}: real - simulated; effects: {names or 'none'}"
        # Shade located spans.
        for s in j.get("located", []):
            i = CH.index(s["channel"]) if s["channel"] in CH else None
            if i is not None:
                axes[i].axvspan(s["t_start"] - t0, s["t_end"] - t0, color="orange", alpha=0.15)
    fig.suptitle(textwrap.fill(title, 110), fontsize=10)  # many effects: wrap, do not clip
    fig.tight_layout()
    fig.savefig(os.path.join(out_dir, "diagnosis_residual.png"), dpi=110)
    plt.close(fig)
    print(f"plot_diagnosis: wrote {out_dir}/diagnosis_residual.png")
    opath = os.path.join(out_dir, "outages.csv")
    if os.path.exists(opath):
        orows = list(csv.DictReader(open(opath)))
        if orows:
            x = list(range(len(orows)))
            w = 0.27
            fig, ax = plt.subplots(figsize=(10, 4))
            for k, (key, label, color) in enumerate([("sg2_horizontal_m", "SG#2", "tab:orange"),
                                                     ("sg3_horizontal_m", "SG#3", "tab:green"),
                                                     ("real_horizontal_m", "REAL", "tab:blue")]):
                ax.bar([i + (k - 1) * w for i in x], [float(r[key]) for r in orows], w,
                       label=label, color=color)
            ax.set_xticks(x)
            ax.set_xticklabels([f"{float(r['t_start']) - t0:.0f} s\n{100 * float(r['share']):.0f} %"
                                for r in orows], fontsize=8)
            ax.set_xlabel("outage start (since the first bin); share of sum |SG#2 - REAL|")
            ax.set_ylabel("max horizontal drift in outage [m]")
            ax.set_title("Outage errors of SG#2, SG#3 and REAL")
            ax.legend()
            ax.grid(alpha=0.3, axis="y")
            fig.tight_layout()
            fig.savefig(os.path.join(out_dir, "diagnosis_outages.png"), dpi=110)
            plt.close(fig)
            print(f"plot_diagnosis: wrote {out_dir}/diagnosis_outages.png")
    return 0


if __name__ == "__main__":
    if len(sys.argv) != 2:
        print(__doc__, file=sys.stderr)
        sys.exit(2)
    sys.exit(main(sys.argv[1]))
